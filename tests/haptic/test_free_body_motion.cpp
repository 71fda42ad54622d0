// FreeBodyMotion: a free rigid body stepped at the haptic rate. Free fall matches the discrete
// closed form; a torque-free asymmetric body keeps its angular momentum exactly and its energy
// within bounds while ω wanders (the intermediate-axis flip); a body on a contact spring far
// stiffer than explicit Euler could take stays bounded and loses energy; a step allocates nothing.
#include <khz/haptic/common.hpp>
#include <khz/haptic/world/free_body_motion.hpp>
#include <khz/test/allocation_probe.hpp>
#include <khz/test/fixtures.hpp>

#include <gtest/gtest.h>

#include <cmath>

namespace khz::haptic {
namespace {

using Stiffness = Eigen::Matrix<double, 6, 6>;

/// A 0.3 × 0.2 × 0.1 m block of 1000 kg/m³ (6 kg), centre of mass at (0.15, 0.1, 0.05) in its
/// body frame, with its three different principal moments.
RigidInertia block() {
  RigidInertia inertia;
  const double a = 0.3, b = 0.2, c = 0.1;
  inertia.mass = 1000.0 * a * b * c;
  inertia.centre = Eigen::Vector3d(a, b, c) / 2.0;
  inertia.inertia = Eigen::Vector3d(b * b + c * c, a * a + c * c, a * a + b * b).asDiagonal() *
                    (inertia.mass / 12.0);
  return inertia;
}

TEST(FreeBodyMotion, FallsAsTheDiscreteClosedForm) {
  const Eigen::Vector3d gravity(0.0, 0.0, -9.81);
  FreeBodyMotion body(block(), Eigen::Isometry3d::Identity(), Eigen::Vector3d(1.0, 0.0, 2.0));
  const Eigen::Vector3d start = body.centre();
  constexpr double h = 1e-3;
  constexpr int steps = 500;
  for (int k = 0; k < steps; ++k) {
    ASSERT_TRUE(
        body.step(h, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), Stiffness::Zero(), gravity));
  }
  // v_n = v₀ + n h g; c_n = c₀ + h Σ_{k=1..n} v_k = c₀ + n h v₀ + h² g n(n+1)/2.
  const Eigen::Vector3d v0(1.0, 0.0, 2.0);
  EXPECT_LT((body.velocity() - (v0 + steps * h * gravity)).norm(), 1e-12);
  const Eigen::Vector3d expected =
      start + steps * h * v0 + h * h * gravity * steps * (steps + 1) / 2;
  EXPECT_LT((body.centre() - expected).norm(), 1e-12);
  EXPECT_LT(body.angular_velocity().norm(), 1e-15);
}

TEST(FreeBodyMotion, TorqueFreeSpinKeepsItsAngularMomentumExactly) {
  // Spun mostly about the intermediate axis (y), it tumbles: ω wanders far, L does not.
  const Eigen::Vector3d omega(0.05, 10.0, 0.05);
  const Eigen::Vector3d velocity(0.2, -0.1, 0.3);
  FreeBodyMotion body(block(), Eigen::Isometry3d::Identity(), velocity, omega);
  const Eigen::Vector3d momentum = body.angular_momentum();
  const double energy = body.kinetic_energy();
  double largest_x = 0.0, energy_low = energy, energy_high = energy;
  for (int k = 0; k < 5000; ++k) {
    ASSERT_TRUE(body.step(1e-3, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), Stiffness::Zero(),
                          Eigen::Vector3d::Zero()));
    largest_x = std::max(largest_x, std::abs(body.angular_velocity().x()));
    energy_low = std::min(energy_low, body.kinetic_energy());
    energy_high = std::max(energy_high, body.kinetic_energy());
  }
  EXPECT_LT((body.angular_momentum() - momentum).norm(), 1e-12 * momentum.norm());
  EXPECT_GT(largest_x, 1.0) << "the intermediate axis is unstable: the body tumbles";
  EXPECT_LT(energy_high - energy_low, 0.05 * energy) << "energy " << energy;
  const Eigen::Matrix3d rotation = body.pose().linear();
  EXPECT_LT((rotation.transpose() * rotation - Eigen::Matrix3d::Identity()).norm(), 1e-12);
}

TEST(FreeBodyMotion, ImplicitStepHoldsAStiffSpringThatExplicitEulerCouldNot) {
  // A spring of 10⁷ N/m on 6 kg: ω_n = 1.3·10³ rad/s, h ω_n = 1.3 at 1 kHz (explicit Euler needs
  // h ω_n < 2 and gains energy at any h). The implicit step stays bounded and loses energy.
  const RigidInertia inertia = block();
  FreeBodyMotion body(inertia, Eigen::Isometry3d::Identity(), Eigen::Vector3d(0.0, 0.0, -0.1));
  const double k = 1e7;
  const Eigen::Vector3d rest = body.centre();
  Stiffness stiffness = Stiffness::Zero();
  stiffness.topLeftCorner<3, 3>() = -k * Eigen::Matrix3d::Identity();
  const auto energy = [&] {
    return body.kinetic_energy() + 0.5 * k * (body.centre() - rest).squaredNorm();
  };
  double previous = energy();
  for (int n = 0; n < 2000; ++n) {
    const Eigen::Vector3d force = -k * (body.centre() - rest);
    ASSERT_TRUE(
        body.step(1e-3, force, Eigen::Vector3d::Zero(), stiffness, Eigen::Vector3d::Zero()));
    EXPECT_LE(energy(), previous * (1.0 + 1e-12)) << "step " << n;
    previous = energy();
  }
  EXPECT_LT(body.velocity().norm(), 1e-6);
}

TEST(FreeBodyMotion, RefusesBadInputAndAllocatesNothing) {
  RigidInertia massless = block();
  massless.mass = 0.0;
  EXPECT_TRUE(test::throws_with_message<Error>(
      [&] { FreeBodyMotion(massless, Eigen::Isometry3d::Identity()); },
      "RigidInertia: mass must be finite and > 0 (kg)"));
  RigidInertia flat = block();
  flat.inertia(2, 2) = -1.0;
  EXPECT_TRUE(test::throws_with_message<Error>(
      [&] { FreeBodyMotion(flat, Eigen::Isometry3d::Identity()); }, "positive definite"));
  FreeBodyMotion body(block(), Eigen::Isometry3d::Identity());
  const Eigen::Vector3d nan(std::nan(""), 0.0, 0.0);
  const FreeBodyMotion before = body;
  EXPECT_FALSE(
      body.step(1e-3, nan, Eigen::Vector3d::Zero(), Stiffness::Zero(), Eigen::Vector3d::Zero()));
  EXPECT_FALSE(body.step(0.0, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), Stiffness::Zero(),
                         Eigen::Vector3d::Zero()));
  EXPECT_EQ(body.pose().matrix(), before.pose().matrix());
  test::allocation_count = 0;
  for (int k = 0; k < 100; ++k) {
    body.step(1e-3, Eigen::Vector3d(0, 0, 1), Eigen::Vector3d(0.1, 0, 0), -Stiffness::Identity(),
              Eigen::Vector3d(0, 0, -9.81));
  }
  EXPECT_EQ(test::allocation_count.load(), 0U);
}

}  // namespace
}  // namespace khz::haptic
