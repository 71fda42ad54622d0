// The coupling force and torque (thesis §4.3, eq. 4.13–4.16), their gradients (§4.4, eq. 4.17,
// 4.24; eq. 4.40 where saturated) against central differences, and the saturation profile
// (eq. 4.39).

#include <khz/haptic/coupling/coupling_wrench.hpp>
#include <khz/haptic/coupling/rotation_vector.hpp>
#include <khz/haptic/coupling/saturation.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

namespace khz::haptic {
namespace {

using Matrix6d = Eigen::Matrix<double, 6, 6>;
using Vector6d = Eigen::Matrix<double, 6, 1>;
constexpr double pi = std::numbers::pi;

Eigen::Quaterniond random_rotation(std::mt19937& random) {
  std::normal_distribution<double> normal;
  Eigen::Quaterniond q(normal(random), normal(random), normal(random), normal(random));
  return q.normalized();
}

Eigen::Vector3d random_vector(std::mt19937& random, double scale) {
  std::uniform_real_distribution<double> uniform(-scale, scale);
  return {uniform(random), uniform(random), uniform(random)};
}

Eigen::Quaterniond negated(const Eigen::Quaterniond& q) { return {-q.w(), -q.x(), -q.y(), -q.z()}; }

Vector6d stacked(const CouplingWrench& wrench) {
  Vector6d v;
  v << wrench.force, wrench.torque;
  return v;
}

// The 6×6 derivative of [F_VC; T_VC] with respect to (Δx, Δω): x_s ← x_s + Δx, and
// q_s ← exp(Δω) q_s (world axes about the grasp point), by central differences.
Matrix6d central_differences(const Pose& manipulandum, const Pose& simulation,
                             const CouplingSprings& springs, double h) {
  Matrix6d derivative;
  for (int column = 0; column < 6; ++column) {
    Vector6d sides[2];
    for (int side = 0; side < 2; ++side) {
      Vector6d delta = Vector6d::Zero();
      delta[column] = side == 0 ? h : -h;
      const Pose moved{simulation.position + delta.head<3>(),
                       rotation_quaternion(delta.tail<3>()) * simulation.orientation};
      sides[side] = stacked(coupling_wrench(manipulandum, moved, springs));
    }
    derivative.col(column) = (sides[0] - sides[1]) / (2.0 * h);
  }
  return derivative;
}

Matrix6d analytic(const CouplingWrench& wrench) {
  Matrix6d derivative = Matrix6d::Zero();  // ∂F_VC/∂ω = ∂T_VC/∂x = 0 (eq. 4.17)
  derivative.topLeftCorner<3, 3>() = wrench.force_by_translation;
  derivative.bottomRightCorner<3, 3>() = wrench.torque_by_rotation;
  return derivative;
}

struct GradientCase {
  const char* name;
  CouplingSprings springs;
  double offset;  // m, largest component of x_m − x_s
  bool expect_force_saturated;
  bool expect_torque_saturated;
  double tolerance;  // relative; measured worst of the 40 cases ×3–4 (h²-truncation when saturated)
};

// Random poses, both quaternion hemispheres, angles up to ~170° (the torque direction flips at
// 180°, where no derivative exists); linear, force-saturated and torque-saturated springs.
TEST(CouplingWrench, GradientsMatchCentralDifferences) {
  const double inf = std::numeric_limits<double>::infinity();
  const GradientCase cases[] = {
      {"linear", {500.0, 2.0, inf, inf}, 0.02, false, false, 1e-10},
      {"force saturated", {500.0, 2.0, 4.0, inf}, 0.05, true, false, 1.5e-8},
      {"torque saturated", {500.0, 2.0, inf, 0.3}, 0.02, false, true, 1e-10},
  };
  std::mt19937 random(4711);
  for (const GradientCase& c : cases) {
    int checked = 0;
    while (checked < 40) {
      const Pose simulation{random_vector(random, 1.0), random_rotation(random)};
      Pose manipulandum{simulation.position + random_vector(random, c.offset),
                        random_rotation(random)};
      const Eigen::Quaterniond difference =
          manipulandum.orientation * simulation.orientation.conjugate();
      if (std::abs(difference.w()) < 0.09) continue;  // within ~10° of a half turn
      if (checked % 2 == 1) manipulandum.orientation = negated(manipulandum.orientation);
      const CouplingWrench wrench = coupling_wrench(manipulandum, simulation, c.springs);
      if (wrench.force_saturated != c.expect_force_saturated ||
          wrench.torque_saturated != c.expect_torque_saturated) {
        continue;
      }
      const Matrix6d expected = central_differences(manipulandum, simulation, c.springs, 1e-6);
      const Matrix6d actual = analytic(wrench);
      EXPECT_LE((actual - expected).norm(), c.tolerance * expected.norm())
          << c.name << "\nanalytic\n"
          << actual << "\ncentral differences\n"
          << expected;
      ++checked;
    }
  }
}

// With small differences the coupling is two linear springs: F = k_VC (x_m − x_s), and the
// torque k_VC,torque sin(θ/2) along the axis turning the simulation object onto the manipulandum.
TEST(CouplingWrench, LinearSpringsFollowEquations4_13And4_14) {
  const CouplingSprings springs{300.0, 4.0};
  const Eigen::Vector3d axis = Eigen::Vector3d(1.0, -2.0, 0.5).normalized();
  const double angle = 0.7;
  const Pose simulation{{0.1, 0.2, 0.3}, Eigen::Quaterniond(Eigen::AngleAxisd(0.4, axis))};
  const Pose manipulandum{{0.1, 0.25, 0.29},
                          Eigen::Quaterniond(Eigen::AngleAxisd(0.4 + angle, axis))};
  const CouplingWrench wrench = coupling_wrench(manipulandum, simulation, springs);
  const Eigen::Vector3d force = 300.0 * Eigen::Vector3d(0.0, 0.05, -0.01);
  EXPECT_LE((wrench.force - force).norm(), 1e-12 * force.norm());
  const Eigen::Vector3d torque = 4.0 * std::sin(angle / 2.0) * axis;
  EXPECT_LE((wrench.torque - torque).norm(), 1e-14);
  EXPECT_EQ(wrench.force_by_translation, -300.0 * Eigen::Matrix3d::Identity());
  EXPECT_EQ(wrench.linear_force, wrench.force);
  EXPECT_EQ(wrench.linear_torque, wrench.torque);
  // Small angles: ∂T/∂ω → −k_VC,torque/2 I.
  const Pose aligned{manipulandum.position, manipulandum.orientation};
  EXPECT_LE((coupling_wrench(manipulandum, aligned, springs).torque_by_rotation +
             2.0 * Eigen::Matrix3d::Identity())
                .norm(),
            1e-15);
}

// q and −q are one rotation: negating either orientation (or both) leaves the torque and its
// gradient unchanged, up to and including a half turn.
TEST(CouplingWrench, OppositeQuaternionsGiveTheSameTorque) {
  const CouplingSprings springs{500.0, 3.0};
  const Eigen::Vector3d axis = Eigen::Vector3d(0.3, 0.9, -0.2).normalized();
  const Pose simulation{{0.0, 0.0, 0.0}, Eigen::Quaterniond(Eigen::AngleAxisd(0.3, axis))};
  for (const double angle : {0.5, 2.0, pi - 1e-9, pi, pi + 1e-9, 4.0, 2.0 * pi - 0.1}) {
    const Eigen::Quaterniond rotation(Eigen::AngleAxisd(angle, Eigen::Vector3d::UnitZ()));
    const Pose manipulandum{{0.0, 0.0, 0.0}, rotation * simulation.orientation};
    const CouplingWrench reference = coupling_wrench(manipulandum, simulation, springs);
    const Pose flipped_m{manipulandum.position, negated(manipulandum.orientation)};
    const Pose flipped_s{simulation.position, negated(simulation.orientation)};
    for (const auto& [m, s] : {std::pair{flipped_m, simulation}, std::pair{manipulandum, flipped_s},
                               std::pair{flipped_m, flipped_s}}) {
      const CouplingWrench wrench = coupling_wrench(m, s, springs);
      EXPECT_LE((wrench.torque - reference.torque).norm(), 1e-14) << "angle " << angle;
      EXPECT_LE((wrench.torque_by_rotation - reference.torque_by_rotation).norm(), 1e-14)
          << "angle " << angle;
    }
  }
  // Exactly a half turn: the torque has its full magnitude along ±z.
  const Pose identity;
  const Pose half_turn{{0.0, 0.0, 0.0}, Eigen::Quaterniond(0.0, 0.0, 0.0, 1.0)};
  const CouplingWrench half = coupling_wrench(half_turn, identity, springs);
  EXPECT_EQ(half.torque, Eigen::Vector3d(0.0, 0.0, 3.0));
  EXPECT_EQ(coupling_wrench({{}, negated(half_turn.orientation)}, identity, springs).torque,
            half.torque);
}

// A quaternion with negative scalar part writes a rotation by θ ∈ (π, 2π) about a; the same
// rotation is 2π − θ about −a, and that is the way the torque must turn the simulation object.
TEST(CouplingWrench, TorqueTurnsTheShortWayBeyondAHalfTurn) {
  const CouplingSprings springs{500.0, 2.0};
  const Eigen::Vector3d axis = Eigen::Vector3d(1.0, 1.0, 1.0).normalized();
  const Pose simulation;
  for (const double angle : {pi + 0.01, 1.25 * pi, 1.5 * pi, 1.9 * pi, 2.0 * pi - 1e-6}) {
    const Eigen::Quaterniond q(Eigen::AngleAxisd(angle, axis));
    ASSERT_LT(q.w(), 0.0);
    const CouplingWrench wrench = coupling_wrench({{}, q}, simulation, springs);
    const Eigen::Vector3d expected = -2.0 * std::sin(pi - angle / 2.0) * axis;
    EXPECT_LE((wrench.torque - expected).norm(), 1e-14) << "angle " << angle;
    EXPECT_LT(wrench.torque.dot(axis), 0.0) << "angle " << angle;
    EXPECT_LE((rotation_vector(q) + (2.0 * pi - angle) * axis).norm(), 1e-12) << "angle " << angle;
  }
}

// Eq. 4.39: linear up to P/2, then P(1 − ½ e^{1−2m/P}); continuous with a continuous derivative
// at the joint, increasing, and below P.
TEST(Saturation, ProfileIsC1AtTheJointAndApproachesThePlateau) {
  const double plateau = 6.0;
  EXPECT_EQ(saturation_profile(2.0, plateau), 2.0);
  EXPECT_EQ(saturation_profile(3.0, plateau), 3.0);
  const double h = 1e-7;
  EXPECT_NEAR(saturation_profile(3.0 + h, plateau), 3.0 + h, 1e-13);
  const double right_slope =
      (saturation_profile(3.0 + 2 * h, plateau) - saturation_profile(3.0 + h, plateau)) / h;
  EXPECT_NEAR(right_slope, 1.0, 1e-6);
  double previous = 3.0;
  for (double m = 3.5; m < 100.0; m += 0.5) {
    const double f = saturation_profile(m, plateau);
    EXPECT_GT(f, previous) << m;
    EXPECT_LT(f, plateau) << m;
    previous = f;
  }
  EXPECT_NEAR(saturation_profile(60.0, plateau), plateau - 3.0 * std::exp(-19.0), 1e-14);
  EXPECT_NEAR(saturation_profile(150.0, plateau), plateau, 1e-15);
  EXPECT_EQ(saturation_profile(1e300, std::numeric_limits<double>::infinity()), 1e300);
  // In terms of the stretch r: F_VC,max (1 − ½ exp(2 k_VC (r_lin − r) / F_VC,max)).
  const double k = 400.0, r_lin = plateau / (2.0 * k), r = 0.05;
  EXPECT_NEAR(saturation_profile(k * r, plateau),
              plateau * (1.0 - 0.5 * std::exp(2.0 * k * (r_lin - r) / plateau)), 1e-14);
}

TEST(Saturation, KeepsTheDirection) {
  const Eigen::Vector3d linear(30.0, -40.0, 0.0);
  const SaturatedVector saturated = saturate(linear, 8.0);
  EXPECT_TRUE(saturated.saturated);
  EXPECT_NEAR(saturated.value.norm(), saturation_profile(50.0, 8.0), 1e-14);
  EXPECT_LE((saturated.value.normalized() - linear.normalized()).norm(), 1e-15);
  const SaturatedVector small = saturate(Eigen::Vector3d(1.0, 2.0, 2.0), 8.0);
  EXPECT_FALSE(small.saturated);
  EXPECT_EQ(small.jacobian, Eigen::Matrix3d::Identity());
}

// The rotation-vector maps against Eigen's angle-axis conversions, small angles included.
TEST(RotationVector, MatchesAngleAxis) {
  const Eigen::Vector3d axis = Eigen::Vector3d(-0.2, 0.7, 0.4).normalized();
  for (const double angle : {0.0, 1e-12, 1e-6, 9e-5, 1.1e-4, 0.3, 2.0, pi - 1e-7}) {
    const Eigen::Quaterniond expected(Eigen::AngleAxisd(angle, axis));
    const Eigen::Quaterniond q = rotation_quaternion(angle * axis);
    EXPECT_LE((q.coeffs() - expected.coeffs()).norm(), 1e-16) << angle;
    EXPECT_LE((rotation_vector(expected) - angle * axis).norm(), 4e-16 * std::max(angle, 1.0))
        << angle;
    EXPECT_LE((rotation_vector(negated(expected)) - angle * axis).norm(),
              4e-16 * std::max(angle, 1.0))
        << angle;
  }
}

}  // namespace
}  // namespace khz::haptic
