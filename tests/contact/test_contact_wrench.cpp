// ContactWrench::accumulate: what a multi-body cycle sums over the pairs a held object is in.
#include <khz/contact/query/contact_result.hpp>
#include <khz/contact/query/contact_wrench.hpp>

#include <gtest/gtest.h>

namespace khz::contact {
namespace {

ContactWrench pair_wrench(double scale, int level, bool complete, bool reset) {
  ContactWrench w;
  w.force = scale * Eigen::Vector3d(1.0, -2.0, 0.5);
  w.torque = scale * Eigen::Vector3d(0.25, 0.0, -1.0);
  w.force_by_translation = scale * Eigen::Matrix3d::Identity();
  w.force_by_rotation = scale * Eigen::Matrix3d::Constant(2.0);
  w.torque_by_translation = scale * Eigen::Matrix3d::Constant(-0.5);
  w.torque_by_rotation = -scale * Eigen::Matrix3d::Identity();
  w.statistics.nodes_traversed = 100 * level;
  w.statistics.nodes_skipped = 7;
  w.statistics.points_in_contact = 3 * level;
  w.statistics.deepest_level = level;
  w.statistics.complete = complete;
  w.statistics.coherence_reset = reset;
  w.statistics.microseconds = 1.5 * level;
  w.statistics.deepest_penetration = 1e-3 * level;
  return w;
}

TEST(ContactWrench, AccumulateSumsEveryTermAndCombinesTheCounters) {
  ContactWrench sum;  // a cycle's sum starts empty
  const ContactWrench a = pair_wrench(1.0, 2, true, false);
  const ContactWrench b = pair_wrench(4.0, 5, false, true);
  sum.accumulate(a);
  sum.accumulate(b);
  // Dyadic values: the sums are exact.
  EXPECT_EQ(sum.force, a.force + b.force);
  EXPECT_EQ(sum.torque, a.torque + b.torque);
  EXPECT_EQ(sum.force_by_translation, 5.0 * Eigen::Matrix3d::Identity());
  EXPECT_EQ(sum.force_by_rotation, Eigen::Matrix3d::Constant(10.0));
  EXPECT_EQ(sum.torque_by_translation, Eigen::Matrix3d::Constant(-2.5));
  EXPECT_EQ(sum.torque_by_rotation, -5.0 * Eigen::Matrix3d::Identity());
  EXPECT_EQ(sum.statistics.nodes_traversed, 700);
  EXPECT_EQ(sum.statistics.nodes_skipped, 14);
  EXPECT_EQ(sum.statistics.points_in_contact, 21);
  EXPECT_EQ(sum.statistics.deepest_level, 5);
  EXPECT_EQ(sum.statistics.deepest_penetration, 5e-3);  // the deeper pair's
  EXPECT_FALSE(sum.statistics.complete);                // one pair stopped early
  EXPECT_TRUE(sum.statistics.coherence_reset);
  EXPECT_EQ(sum.statistics.microseconds, 10.5);
}

TEST(ContactWrench, AnEmptySumOfNoPairsIsZeroCompleteAndBeforeTheFirstLevel) {
  const ContactWrench none;
  EXPECT_EQ(none.force, Eigen::Vector3d::Zero());
  EXPECT_EQ(none.force_by_rotation, Eigen::Matrix3d::Zero());
  EXPECT_EQ(none.statistics.deepest_level, -1);
  EXPECT_EQ(none.statistics.deepest_penetration, 0.0);
  EXPECT_TRUE(none.statistics.complete);
  // A ContactResult is a ContactWrench with the reduced forces: it accumulates as one.
  ContactResult result;
  result.accumulate(pair_wrench(2.0, 1, true, false));
  EXPECT_EQ(result.force, 2.0 * Eigen::Vector3d(1.0, -2.0, 0.5));
  EXPECT_EQ(result.pointshell_reduced_force.size(), 0);
}

}  // namespace
}  // namespace khz::contact
