#include <khz/reduced/subspace/reduced_point_forces.hpp>
#include <khz/test/allocation_probe.hpp>

#include <gtest/gtest.h>

#include <limits>
#include <vector>

namespace khz::reduced {
namespace {

TEST(ReducedPointForces, EqualsTheDenseProjectionOfTheFullForce) {
  const Eigen::Index vertices = 50, r = 7;
  const Eigen::MatrixXd basis = Eigen::MatrixXd::Random(3 * vertices, r);
  ForceLoad load;
  load.forces = {
      {3, {1.0, -2.0, 0.5}}, {49, {0.0, 0.0, 4.0}}, {3, {-0.25, 1.0, 1.0}}, {0, {2, 2, 2}}};
  Eigen::VectorXd reduced(r);
  ASSERT_TRUE(reduced_point_forces(basis, load.forces, reduced));
  const Eigen::VectorXd expected = basis.transpose() * load.to_vector(vertices);
  EXPECT_LT((reduced - expected).norm(), 1e-14 * expected.norm());
}

TEST(ReducedPointForces, NoForcesGiveZero) {
  const Eigen::MatrixXd basis = Eigen::MatrixXd::Random(30, 4);
  Eigen::VectorXd reduced = Eigen::VectorXd::Ones(4);
  EXPECT_TRUE(reduced_point_forces(basis, {}, reduced));
  EXPECT_TRUE(reduced.isZero(0.0));
}

TEST(ReducedPointForces, BadVerticesAndForcesReturnFalseAndZero) {
  const Eigen::MatrixXd basis = Eigen::MatrixXd::Random(30, 4);  // 10 vertices
  Eigen::VectorXd reduced(4);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (const PointForce& bad :
       {PointForce{10, {1, 0, 0}}, PointForce{-1, {1, 0, 0}}, PointForce{2, {nan, 0, 0}}}) {
    const std::vector<PointForce> forces{{1, {1, 1, 1}}, bad};
    reduced.setOnes();
    EXPECT_FALSE(reduced_point_forces(basis, forces, reduced));
    EXPECT_TRUE(reduced.isZero(0.0));
  }
}

TEST(ReducedPointForces, AllocatesNothing) {
  const Eigen::MatrixXd basis = Eigen::MatrixXd::Random(300, 15);
  const std::vector<PointForce> forces{{4, {1, 2, 3}}, {99, {-1, 0, 2}}};
  Eigen::VectorXd reduced(15);
  test::allocation_count = 0;
  const bool ok = reduced_point_forces(basis, forces, reduced);
  EXPECT_EQ(test::allocation_count.load(), 0u);
  EXPECT_TRUE(ok);
}

}  // namespace
}  // namespace khz::reduced
