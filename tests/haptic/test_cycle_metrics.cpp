// CycleMetrics: the smoothness, jitter, residual, penetration and energy figures of a hand's
// cycles, each checked against the same figure computed directly (sorted quantiles, the work of
// a known force over a known motion).
#include <khz/haptic/coupling/rotation_vector.hpp>
#include <khz/haptic/world/cycle_metrics.hpp>
#include <khz/test/fixtures.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <numeric>
#include <random>
#include <vector>

namespace khz::haptic {
namespace {

using test::throws_with_message;

/// Nearest-rank quantile of `values` (sorted here).
double nearest_rank(std::vector<double> values, double fraction) {
  std::sort(values.begin(), values.end());
  const auto rank = static_cast<std::size_t>(std::ceil(fraction * values.size()));
  return values[std::max<std::size_t>(rank, 1) - 1];
}

CycleRecord at_time(int cycle) {
  CycleRecord r;
  r.time = 1e-3 * cycle;
  r.device_valid = r.contact_valid = r.coupling_valid = true;
  return r;
}

// Force jumps spread over eight decades: the percentiles agree with sorted ones to 2 %, the
// maximum and the peak exactly, whatever the units.
TEST(CycleMetrics, JumpQuantilesMatchTheSortedJumpsToTwoPercent) {
  std::mt19937 random(7);
  std::uniform_real_distribution<double> exponent(-6.0, 2.0);
  std::uniform_real_distribution<double> direction(-1.0, 1.0);
  CycleMetrics metrics;
  std::vector<double> jumps;
  Eigen::Vector3d force = Eigen::Vector3d::Zero();
  double peak = 0.0;
  for (int i = 0; i < 20000; ++i) {
    CycleRecord r = at_time(i);
    if (i > 0) {
      const Eigen::Vector3d step =
          std::pow(10.0, exponent(random)) *
          Eigen::Vector3d(direction(random), direction(random), direction(random)).normalized();
      force += step;
      jumps.push_back(step.norm());
    }
    r.contact.force = force;
    r.rendered.force = 0.5 * force;
    peak = std::max(peak, force.norm());
    metrics.record(r, WorkspaceMapping{});
  }
  const CycleMetricsSummary s = metrics.summary();
  EXPECT_EQ(s.cycles, 20000);
  EXPECT_EQ(s.contact_force_jump.count, 19999);
  for (const auto& [figure, fraction] :
       {std::pair{s.contact_force_jump.p50, 0.5}, std::pair{s.contact_force_jump.p99, 0.99}}) {
    const double exact = nearest_rank(jumps, fraction);
    EXPECT_NEAR(figure, exact, 0.02 * exact) << "quantile " << fraction;
  }
  // The rendered force jumps by half the contact force's: the same to round-off.
  EXPECT_NEAR(s.rendered_force_jump.p99, 0.5 * nearest_rank(jumps, 0.99),
              0.02 * nearest_rank(jumps, 0.99));
  EXPECT_NEAR(s.contact_force_jump.max, *std::max_element(jumps.begin(), jumps.end()), 1e-12);
  const double mean = std::accumulate(jumps.begin(), jumps.end(), 0.0) / jumps.size();
  EXPECT_NEAR(s.contact_force_jump.mean, mean, 1e-12 * mean);
  EXPECT_EQ(s.peak_contact_force, peak);
  EXPECT_EQ(s.contact_torque_jump.max, 0.0);
  EXPECT_EQ(s.contact_torque_jump.p99, 0.0);
}

// The passivity observer against the work of a known wrench over a known device motion, through
// a mapping that scales, turns and moves the device's workspace: a force held against the motion
// takes energy from the hand (positive), one along it gives energy (negative), and a torque does
// work over the turn.
TEST(CycleMetrics, PassivityObserverIsTheWorkOfTheWrenchSentOverTheDeviceMotion) {
  WorkspaceMapping mapping;
  mapping.scale = 4.0;
  mapping.offset.orientation =
      Eigen::Quaterniond(Eigen::AngleAxisd(0.7, Eigen::Vector3d(1.0, 2.0, -1.0).normalized()));
  mapping.offset.position = Eigen::Vector3d(0.3, -0.1, 0.2);
  const Eigen::Matrix3d R = mapping.offset.orientation.toRotationMatrix();
  // The device moves along +x (device axes) at 10 mm/s and turns about its z at 0.5 rad/s.
  const auto device_position = [](int i) { return Eigen::Vector3d(1e-5 * i, 0.0, 0.0); };
  const auto device_turn = [](int i) {
    return Eigen::AngleAxisd(5e-4 * i, Eigen::Vector3d::UnitZ());
  };
  const Eigen::Vector3d force_sent(-2.0, 1.0, 0.0);  // device N: against the motion along x
  const Eigen::Vector3d torque_sent(0.0, 0.0, 0.1);  // device N·m: along the turn
  CycleMetrics metrics;
  double energy = 0.0;
  const int cycles = 1000;
  for (int i = 0; i < cycles; ++i) {
    CycleRecord r = at_time(i);
    r.manipulandum.position = mapping.offset.position + R * (mapping.scale * device_position(i));
    r.manipulandum.orientation = mapping.offset.orientation * Eigen::Quaterniond(device_turn(i));
    r.rendered.force = force_sent;
    r.rendered.torque = torque_sent;
    energy = metrics.record(r, mapping);
  }
  const double moved = 1e-5 * (cycles - 1), turned = 5e-4 * (cycles - 1);
  const double expected = -(force_sent.x() * moved + torque_sent.z() * turned);
  EXPECT_NEAR(energy, expected, 1e-12);
  EXPECT_NEAR(metrics.summary().energy, expected, 1e-12);
  // 2 N · 9.99 mm − 0.1 N·m · 0.4995 rad < 0: the torque gives more than the force takes.
  EXPECT_LT(expected, 0.0);
  EXPECT_NEAR(metrics.summary().lowest_energy, expected, 1e-12);
}

// Jitter counts the simulation's steps only once the manipulandum has been still for
// settle_time: a hand moving, then stopping, with a simulation that settles and then shakes by
// ±0.5 µm, reports the shake and not the approach.
TEST(CycleMetrics, JitterIsTheSimulationsStepAfterTheManipulandumHasBeenStill) {
  CycleMetricsOptions options;
  options.settle_time = 0.1;
  CycleMetrics metrics(options);
  const int moving = 300, cycles = 1000;
  int counted = 0;
  for (int i = 0; i < cycles; ++i) {
    CycleRecord r = at_time(i);
    const int t = std::min(i, moving);
    r.manipulandum.position = Eigen::Vector3d(0.0, 0.0, -2e-4 * t);  // 0.2 m/s, then still
    r.manipulandum.orientation =
        Eigen::Quaterniond(Eigen::AngleAxisd(1e-3 * t, Eigen::Vector3d::UnitX()));
    // The simulation follows 2 cycles late and shakes by ±0.5 µm and ±2e-5 rad once still.
    const int late = std::min(std::max(i - 2, 0), moving);
    const double shake = i > moving + 50 ? (i % 2 == 0 ? 0.5e-6 : -0.5e-6) : 0.0;
    r.simulation.position = Eigen::Vector3d(shake, 0.0, -2e-4 * late);
    r.simulation.orientation =
        Eigen::Quaterniond(Eigen::AngleAxisd(1e-3 * late + 40.0 * shake, Eigen::Vector3d::UnitX()));
    metrics.record(r, WorkspaceMapping{});
    // Still since cycle `moving` (its step from moving − 1 was the last motion).
    if (i >= moving + 1 && r.time - at_time(moving).time >= options.settle_time) ++counted;
  }
  const CycleMetricsSummary s = metrics.summary();
  EXPECT_EQ(s.still_translation.count, counted);
  EXPECT_NEAR(s.still_translation.max, 1e-6, 1e-15);
  EXPECT_NEAR(s.still_translation.p50, 1e-6, 0.02e-6);
  EXPECT_NEAR(s.still_rotation.max, 4e-5, 1e-12);
}

// The residual counts only cycles in contact whose coupling was unsaturated; penetration keeps
// the deepest point in metres and in voxels.
TEST(CycleMetrics, ResidualCountsUnsaturatedContactAndPenetrationKeepsTheDeepest) {
  CycleMetrics metrics;
  for (int i = 0; i < 10; ++i) {
    CycleRecord r = at_time(i);
    r.contact.statistics.points_in_contact = i < 8 ? 5 : 0;
    r.coupling_saturated = i == 3;
    r.residual.force = Eigen::Vector3d(0.0, 0.1 * (i + 1), 0.0);
    r.residual.torque = Eigen::Vector3d(1e-3, 0.0, 0.0);
    r.contact.statistics.deepest_penetration = 1e-4 * (i % 4);
    r.penetration_voxels = 0.1 * (i % 4);
    metrics.record(r, WorkspaceMapping{});
  }
  const CycleMetricsSummary s = metrics.summary();
  EXPECT_EQ(s.residual_force.count, 7);           // cycles 0–7 but 3
  EXPECT_NEAR(s.residual_force.max, 0.8, 1e-15);  // cycle 7
  EXPECT_NEAR(s.residual_torque.p99, 1e-3, 0.02e-3);
  EXPECT_DOUBLE_EQ(s.deepest_penetration, 3e-4);
  EXPECT_NEAR(s.deepest_penetration_voxels, 0.3, 1e-15);
  metrics.clear();
  EXPECT_EQ(metrics.summary().cycles, 0);
  EXPECT_EQ(metrics.summary().residual_force.count, 0);
}

TEST(CycleMetrics, RefusesNegativeOrNonFiniteSettings) {
  CycleMetricsOptions options;
  options.still_speed = -1.0;
  EXPECT_TRUE(throws_with_message<Error>([&] { CycleMetrics m(options); }, "still_speed"));
  options = {};
  options.settle_time = std::numeric_limits<double>::infinity();
  EXPECT_TRUE(throws_with_message<Error>([&] { CycleMetrics m(options); }, "settle_time"));
}

}  // namespace
}  // namespace khz::haptic
