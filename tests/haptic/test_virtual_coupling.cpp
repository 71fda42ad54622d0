// VirtualCoupling (thesis ch. 4): one haptic cycle against contact results with known gradients —
// Newton steps in free space, static damping (§4.8), speed limits (§4.6), saturation and
// rendering (§4.9), degenerate contact (§4.10, eq. 4.41), the stiffness bound (§4.7), bad input.

#include <khz/test/allocation_probe.hpp>
#include <khz/test/fixtures.hpp>

#include <khz/haptic/coupling/equilibrium.hpp>
#include <khz/haptic/coupling/rotation_vector.hpp>
#include <khz/haptic/coupling/saturation.hpp>
#include <khz/haptic/coupling/stiffness_bound.hpp>
#include <khz/haptic/coupling/virtual_coupling.hpp>

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>

#include <cmath>
#include <functional>
#include <limits>
#include <numbers>
#include <vector>

namespace khz::haptic {
namespace {

using contact::ContactWrench;
constexpr double pi = std::numbers::pi;
constexpr double unlimited = CouplingOptions::unlimited;

// Pure Newton steps: no damping, no speed limits, no saturation.
CouplingOptions newton_options() {
  CouplingOptions options;
  options.stiffness = 500.0;
  options.torque_stiffness = 2.0;
  options.static_damping = 0.0;
  options.max_speed = unlimited;
  options.max_angular_speed = unlimited;
  return options;
}

Pose translated(const Eigen::Vector3d& position) { return {position, {1.0, 0.0, 0.0, 0.0}}; }

Pose rotated(const Eigen::Vector3d& position, double angle, const Eigen::Vector3d& axis) {
  return {position, Eigen::Quaterniond(Eigen::AngleAxisd(angle, axis.normalized()))};
}

// The angle (rad) between two orientations.
double angle_between(const Eigen::Quaterniond& a, const Eigen::Quaterniond& b) {
  return rotation_vector(a * b.conjugate()).norm();
}

// The motion of one step: (Δx, Δω), Δω in world axes.
struct Motion {
  Eigen::Vector3d translation;
  Eigen::Vector3d rotation;
};

Motion motion(const Pose& before, const Pose& after) {
  return {after.position - before.position,
          rotation_vector(after.orientation * before.orientation.conjugate())};
}

// The linear system the coupling solves this cycle, for comparisons with LU.
EquilibriumSystem system_of(const VirtualCoupling& coupling, const Pose& manipulandum,
                            const ContactWrench& contact) {
  return equilibrium_system(
      coupling_wrench(manipulandum, coupling.simulation_pose(), coupling.options().springs()),
      contact);
}

TEST(VirtualCoupling, FreeSpaceNewtonStepsReachTheManipulandum) {
  VirtualCoupling coupling(newton_options());
  const Pose manipulandum = rotated({0.01, -0.02, 0.005}, 0.5, {1.0, 2.0, -1.0});
  const ContactWrench free_space;
  CouplingStep step = coupling.step(manipulandum, free_space);
  ASSERT_TRUE(step.valid);
  EXPECT_EQ(step.degenerate_dimension, 0);
  // The force is linear: one step is exact. The torque is not (Newton: θ → 2 tan(θ/2)).
  EXPECT_LE((step.simulation.position - manipulandum.position).norm(), 1e-17);
  EXPECT_NEAR(angle_between(step.simulation.orientation, manipulandum.orientation),
              2.0 * std::tan(0.25) - 0.5, 1e-15);
  for (int cycle = 0; cycle < 4; ++cycle) step = coupling.step(manipulandum, free_space);
  EXPECT_LE(angle_between(step.simulation.orientation, manipulandum.orientation), 1e-15);
  EXPECT_LE(step.rendered.force.norm(), 1e-14);
  EXPECT_LE(step.rendered.torque.norm(), 1e-15);
  EXPECT_EQ(coupling.simulation_pose().position, step.simulation.position);
}

// The residual a step reports is eq. 4.1–4.2's net wrench where the step started: the contact
// plus the coupling springs, k_VC (x_m − x_s) (eq. 4.13) and k_VC,torque sin(θ/2) along the axis
// (eq. 4.14), before the step moves anything.
TEST(VirtualCoupling, TheResidualIsTheNetWrenchWhereTheStepStarted) {
  VirtualCoupling coupling(newton_options());
  const Eigen::Vector3d axis = Eigen::Vector3d(1.0, -2.0, 0.5).normalized();
  const double angle = 0.3;
  const Pose manipulandum = rotated({0.004, -0.001, 0.002}, angle, axis);
  ContactWrench contact;
  contact.force = Eigen::Vector3d(0.5, 1.0, -2.0);
  contact.torque = Eigen::Vector3d(0.01, 0.0, -0.02);
  contact.force_by_translation = -2000.0 * Eigen::Matrix3d::Identity();
  const CouplingStep step = coupling.step(manipulandum, contact);
  ASSERT_TRUE(step.valid);
  EXPECT_LE((step.residual.force - (contact.force + 500.0 * manipulandum.position)).norm(), 1e-15);
  EXPECT_LE((step.residual.torque - (contact.torque + 2.0 * std::sin(angle / 2.0) * axis)).norm(),
            1e-15);
}

// §4.8: each cycle moves by (1 − α) of the Newton step, so in free space the gap shrinks by α.
TEST(VirtualCoupling, StaticDampingMovesAFractionOfTheStep) {
  CouplingOptions options = newton_options();
  options.static_damping = 0.5;
  VirtualCoupling coupling(options);
  const Eigen::Vector3d target(0.02, 0.01, -0.03);
  for (int cycle = 1; cycle <= 10; ++cycle) {
    const CouplingStep step = coupling.step(translated(target), ContactWrench{});
    const Eigen::Vector3d gap = target - step.simulation.position;
    EXPECT_LE((gap - std::pow(0.5, cycle) * target).norm(), 1e-17) << cycle;
    // Rendered: −k_VC (x_m − x_s) at the new pose.
    EXPECT_LE((step.rendered.force + 500.0 * gap).norm(), 1e-13) << cycle;
  }
}

// §4.6: the simulation object moves at most max_speed × period and max_angular_speed × period
// per cycle, towards where the solve would take it.
TEST(VirtualCoupling, SpeedLimitsClampThePerCycleMotion) {
  CouplingOptions options = newton_options();
  options.max_speed = 0.5;          // 0.5 mm per 1 ms cycle
  options.max_angular_speed = 1.0;  // 1 mrad per cycle
  VirtualCoupling coupling(options);
  const Eigen::Vector3d axis = Eigen::Vector3d(0.0, 1.0, 1.0).normalized();
  const Pose manipulandum = rotated({0.06, 0.0, -0.08}, 1.0, axis);
  const CouplingStep step = coupling.step(manipulandum, ContactWrench{});
  EXPECT_TRUE(step.speed_limited);
  EXPECT_TRUE(step.angular_speed_limited);
  const Motion moved = motion(Pose{}, step.simulation);
  EXPECT_NEAR(moved.translation.norm(), 5e-4, 1e-17);
  EXPECT_LE((moved.translation.normalized() - manipulandum.position.normalized()).norm(), 1e-15);
  EXPECT_NEAR(moved.rotation.norm(), 1e-3, 1e-16);
  EXPECT_LE((moved.rotation.normalized() - axis).norm(), 1e-12);
  EXPECT_DOUBLE_EQ(options.max_translation_per_cycle(), 5e-4);
  EXPECT_DOUBLE_EQ(options.max_rotation_per_cycle(), 1e-3);

  // Close by, nothing is limited.
  const Pose near{step.simulation.position + Eigen::Vector3d(1e-4, 0.0, 0.0),
                  step.simulation.orientation};
  const CouplingStep small = coupling.step(near, ContactWrench{});
  EXPECT_FALSE(small.speed_limited);
  EXPECT_FALSE(small.angular_speed_limited);
  EXPECT_LE((small.simulation.position - near.position).norm(), 1e-17);
}

// §4.9: the simulation's coupling force saturates to F_VC,max (eq. 4.39) while the device gets
// −k_VC (x_m − x_s) clamped to its own maximum, direction kept; torques likewise, with the
// torque plateau F_VC,max × object_radius.
TEST(VirtualCoupling, SaturationAndRenderingClampsKeepTheDirection) {
  CouplingOptions options = newton_options();
  options.max_speed = 0.5;
  options.max_angular_speed = 1.0;
  options.saturation_force = 4.0;
  options.object_radius = 0.05;  // torque plateau 0.2 N·m
  options.max_rendered_force = 10.0;
  options.max_rendered_torque = 0.5;
  VirtualCoupling coupling(options);
  EXPECT_DOUBLE_EQ(options.springs().saturation_torque, 0.2);
  const Eigen::Vector3d axis(0.0, 0.0, 1.0);
  const Pose manipulandum = rotated({0.06, 0.0, -0.08}, 1.0, axis);
  const CouplingStep step = coupling.step(manipulandum, ContactWrench{});
  ASSERT_TRUE(step.speed_limited);  // the simulation object lags 0.0995 m: k_VC r ≈ 50 N
  EXPECT_TRUE(step.coupling_saturated);
  const Eigen::Vector3d stretch = step.simulation.position - manipulandum.position;
  EXPECT_TRUE(step.force_clamped);
  EXPECT_NEAR(step.rendered.force.norm(), 10.0, 1e-14);
  EXPECT_LE((step.rendered.force.normalized() - stretch.normalized()).norm(), 1e-15);
  EXPECT_NEAR(step.coupling.force.norm(), saturation_profile(500.0 * stretch.norm(), 4.0), 1e-14);
  EXPECT_LE((step.coupling.force.normalized() + stretch.normalized()).norm(), 1e-15);
  // Torque: unsaturated 2 sin(0.4995) ≈ 0.96 N·m, saturated below 0.2, rendered clamped at 0.5.
  EXPECT_TRUE(step.torque_clamped);
  EXPECT_NEAR(step.rendered.torque.norm(), 0.5, 1e-15);
  EXPECT_LE((step.rendered.torque.normalized() + axis).norm(), 1e-12);
  EXPECT_NEAR(step.coupling.torque.norm(),
              saturation_profile(2.0 * std::sin(0.5 * (1.0 - 1e-3)), 0.2), 1e-14);
  EXPECT_LT(step.coupling.torque.norm(), 0.2);

  // Below the device's limit the rendered force is exactly −k_VC (x_m − x_s).
  const Pose near = translated(step.simulation.position + Eigen::Vector3d(0.0, 1e-4, 0.0));
  const CouplingStep small = coupling.step(near, ContactWrench{});
  EXPECT_FALSE(small.force_clamped);
  EXPECT_EQ(small.rendered.force,
            -coupling_wrench(near, small.simulation, options.springs()).linear_force);
}

// A contact whose gradients leave some directions unresisted, saturated coupling, and the
// motion §4.10 prescribes: snap to the manipulandum in those directions, Newton in the others.
struct DegenerateScene {
  ContactWrench contact;
  CouplingOptions options;
  Pose manipulandum;
};

// A square box in a square shaft along x (§4.10): walls stiff in y and z, every rotation
// resisted; the manipulandum 1 m down the shaft, where the saturated coupling force is flat.
TEST(VirtualCoupling, ShaftSnapsAlongItsAxis) {
  DegenerateScene scene;
  scene.options = newton_options();
  scene.options.saturation_force = 5.0;
  const double wall = 2e4, twist = 50.0;  // N/m, N·m/rad
  scene.contact.force_by_translation.diagonal() << 0.0, -wall, -wall;
  scene.contact.torque_by_rotation = -twist * Eigen::Matrix3d::Identity();
  scene.contact.force = {0.0, 2.0, 0.0};
  scene.contact.torque = {0.1, 0.0, 0.0};
  scene.manipulandum = translated({1.0, 0.0, 0.0});
  VirtualCoupling coupling(scene.options);
  const EquilibriumSystem system = system_of(coupling, scene.manipulandum, scene.contact);
  const CouplingStep step = coupling.step(scene.manipulandum, scene.contact);
  ASSERT_TRUE(step.valid);
  EXPECT_EQ(step.degenerate_dimension, 1);
  const Motion moved = motion(Pose{}, step.simulation);
  // Snap along the shaft; across it, F_y over the walls and the flat coupling's F/r = 5 N/m.
  const double f = saturation_profile(500.0, 5.0);
  const Eigen::Vector3d translation(1.0, 2.0 / (wall + f), 0.0);
  EXPECT_LE((moved.translation - translation).norm(), 1e-14);
  EXPECT_LE((moved.rotation - Eigen::Vector3d(0.1 / (1.0 + twist), 0.0, 0.0)).norm(), 1e-15);
  // LU on the same system: the flat direction's stiffness is e^{−199} k_VC.
  EXPECT_GT(solve_equilibrium_lu(system.jacobian, -system.net_wrench).norm(), 1e6);
}

// A box between two planes z = ±h (§4.10): free in x and y, no resistance to spinning about z
// but the coupling's k_VC,torque/2. With rotation_length = 1 (the thesis's mixture of units)
// that spin counts as degenerate too; with the object's size it does not.
TEST(VirtualCoupling, TwoPlanesSnapInTheirPlane) {
  DegenerateScene scene;
  scene.options = newton_options();
  scene.options.saturation_force = 5.0;
  scene.options.torque_stiffness = 4.0;  // 2 N·m/rad
  const double wall = 1e5, tilt = 200.0;
  scene.contact.force_by_translation(2, 2) = -wall;
  scene.contact.torque_by_rotation.diagonal() << -tilt, -tilt, 0.0;
  scene.contact.force = {0.0, 0.0, 3.0};
  scene.contact.torque = {0.2, -0.1, 0.05};
  scene.manipulandum = translated({0.6, 0.8, 0.0});
  const double f = saturation_profile(500.0, 5.0);

  scene.options.rotation_length = 0.1;
  VirtualCoupling scaled(scene.options);
  const CouplingStep step = scaled.step(scene.manipulandum, scene.contact);
  EXPECT_EQ(step.degenerate_dimension, 2);
  const Motion moved = motion(Pose{}, step.simulation);
  EXPECT_LE((moved.translation - Eigen::Vector3d(0.6, 0.8, 3.0 / (wall + f))).norm(), 1e-15);
  const Eigen::Vector3d rotation(0.2 / (2.0 + tilt), -0.1 / (2.0 + tilt), 0.05 / 2.0);
  EXPECT_LE((moved.rotation - rotation).norm(), 1e-15);

  scene.options.rotation_length = 1.0;
  VirtualCoupling thesis(scene.options);
  const CouplingStep mixed = thesis.step(scene.manipulandum, scene.contact);
  EXPECT_EQ(mixed.degenerate_dimension, 3);  // σ = 2 < ε σ₁ = 100: the spin snaps to 0
  EXPECT_LE(
      (motion(Pose{}, mixed.simulation).rotation - Eigen::Vector3d(rotation.x(), rotation.y(), 0.0))
          .norm(),
      1e-15);
}

// By default ℓ is the object's radius when it is given (so a small object's rotations are not
// taken for degenerate), and the thesis's 1 m otherwise.
TEST(VirtualCoupling, RotationLengthDefaultsToTheObjectRadius) {
  CouplingOptions options;
  EXPECT_EQ(options.effective_rotation_length(), 1.0);
  options.object_radius = 0.1;
  EXPECT_EQ(options.effective_rotation_length(), 0.1);
  options.rotation_length = 0.3;
  EXPECT_EQ(options.effective_rotation_length(), 0.3);

  // The two-planes scene below: the default with object_radius = 0.1 steps exactly as ℓ = 0.1.
  DegenerateScene scene;
  scene.options = newton_options();
  scene.options.saturation_force = 5.0;
  scene.options.torque_stiffness = 4.0;
  scene.contact.force_by_translation(2, 2) = -1e5;
  scene.contact.torque_by_rotation.diagonal() << -200.0, -200.0, 0.0;
  scene.contact.torque = {0.2, -0.1, 0.05};
  scene.manipulandum = translated({0.6, 0.8, 0.0});
  scene.options.object_radius = 0.1;
  const CouplingStep automatic =
      VirtualCoupling(scene.options).step(scene.manipulandum, scene.contact);
  scene.options.rotation_length = 0.1;
  const CouplingStep explicit_length =
      VirtualCoupling(scene.options).step(scene.manipulandum, scene.contact);
  EXPECT_EQ(automatic.degenerate_dimension, 2);
  EXPECT_EQ(automatic.degenerate_dimension, explicit_length.degenerate_dimension);
  EXPECT_EQ(automatic.simulation.position, explicit_length.simulation.position);
  EXPECT_EQ(automatic.simulation.orientation.coeffs(),
            explicit_length.simulation.orientation.coeffs());
}

// A ball in a spherical socket (§4.10): contact resists translation only. With the coupling
// torque saturated (plateau F_VC,max × object_radius), no direction of rotation is resisted and
// the simulation object turns onto the manipulandum's orientation (eq. 4.41). In the thesis's
// units (ℓ = 1 m): measured against the object's size, the plateau's sideways pull is not small.
TEST(VirtualCoupling, BallInSocketSnapsItsRotation) {
  DegenerateScene scene;
  scene.options = newton_options();
  scene.options.torque_stiffness = 100.0;
  scene.options.saturation_force = 5.0;
  scene.options.object_radius = 0.05;
  scene.options.rotation_length = 1.0;
  const double socket = 1e4;
  scene.contact.force_by_translation = -socket * Eigen::Matrix3d::Identity();
  scene.contact.force = {1.0, 0.0, 0.0};
  const Eigen::Vector3d axis = Eigen::Vector3d(1.0, -1.0, 2.0).normalized();
  scene.manipulandum = rotated({0.001, 0.0, 0.0}, pi / 2.0, axis);
  VirtualCoupling coupling(scene.options);
  const EquilibriumSystem system = system_of(coupling, scene.manipulandum, scene.contact);
  const CouplingStep step = coupling.step(scene.manipulandum, scene.contact);
  EXPECT_EQ(step.degenerate_dimension, 3);
  EXPECT_TRUE(step.coupling_saturated);
  const Motion moved = motion(Pose{}, step.simulation);
  // F_net = k_VC 0.001 + 1 N against k_VC + the socket.
  EXPECT_LE((moved.translation - Eigen::Vector3d(1.5 / (socket + 500.0), 0.0, 0.0)).norm(), 1e-18);
  EXPECT_LE(angle_between(step.simulation.orientation, scene.manipulandum.orientation), 1e-15);
  EXPECT_GT(solve_equilibrium_lu(system.jacobian, -system.net_wrench).norm(), 1e6);

  // Without torque saturation the rotation is resisted and solved.
  scene.options.object_radius = unlimited;
  VirtualCoupling unsaturated(scene.options);
  EXPECT_EQ(unsaturated.step(scene.manipulandum, scene.contact).degenerate_dimension, 0);
}

// Moving fast in free space (§4.10): the saturated force is flat along the stretch, so that
// direction snaps; across it nothing pulls. The simulation object lands on the manipulandum.
TEST(VirtualCoupling, FastFreeMotionSnapsToTheManipulandum) {
  CouplingOptions options = newton_options();
  options.saturation_force = 5.0;
  VirtualCoupling coupling(options);
  const Pose manipulandum = translated({0.3, -0.4, 1.2});
  const EquilibriumSystem system = system_of(coupling, manipulandum, ContactWrench{});
  const CouplingStep step = coupling.step(manipulandum, ContactWrench{});
  EXPECT_EQ(step.degenerate_dimension, 1);
  EXPECT_LE((step.simulation.position - manipulandum.position).norm(), 1e-15);
  EXPECT_GT(solve_equilibrium_lu(system.jacobian, -system.net_wrench).norm(), 1e6);
}

// A half turn: the torque's gradient −½T̃ does not resist turning about T's own axis, so the
// simulation object snaps along it by π — onto the manipulandum.
TEST(VirtualCoupling, HalfTurnSnapsAboutItsAxis) {
  VirtualCoupling coupling(newton_options());
  const Pose manipulandum{{0.0, 0.0, 0.0}, Eigen::Quaterniond(0.0, 0.0, 0.0, 1.0)};
  const CouplingStep step = coupling.step(manipulandum, ContactWrench{});
  EXPECT_EQ(step.degenerate_dimension, 1);
  EXPECT_LE(angle_between(step.simulation.orientation, manipulandum.orientation), 1e-15);
}

// Beyond a half turn (a quaternion with negative scalar part), the simulation object turns the
// short way round and converges.
TEST(VirtualCoupling, TurnsTheShortWayBeyondAHalfTurn) {
  CouplingOptions options = newton_options();
  options.static_damping = 0.5;
  VirtualCoupling coupling(options);
  const Eigen::Vector3d axis = Eigen::Vector3d(2.0, 1.0, -1.0).normalized();
  const Pose manipulandum = rotated({0.0, 0.0, 0.0}, 1.5 * pi, axis);
  ASSERT_LT(manipulandum.orientation.w(), 0.0);
  CouplingStep step = coupling.step(manipulandum, ContactWrench{});
  EXPECT_LT(motion(Pose{}, step.simulation).rotation.dot(axis), 0.0);
  double angle = pi / 2.0;
  for (int cycle = 0; cycle < 60 && angle > 1e-15; ++cycle) {
    const double previous = angle;
    angle = angle_between(step.simulation.orientation, manipulandum.orientation);
    EXPECT_LT(angle, previous) << cycle;
    step = coupling.step(manipulandum, ContactWrench{});
  }
  EXPECT_LE(angle, 1e-15);
}

TEST(StiffnessBound, SeriesSpringsOfEquation4_31) {
  EXPECT_DOUBLE_EQ(rendered_stiffness_bound(500.0, 1500.0), 375.0);
  EXPECT_EQ(rendered_stiffness_bound(500.0, 0.0), 0.0);
  EXPECT_EQ(rendered_stiffness_bound(500.0, unlimited), 500.0);
  for (const double contact : {1.0, 100.0, 499.0, 501.0, 1e4, 1e9}) {
    EXPECT_LE(rendered_stiffness_bound(500.0, contact), std::min(500.0, contact));
  }
  // ‖J‖₂ of multiplane contact (eq. 4.34): the sum of the stiffnesses iff the normals agree.
  const Eigen::Vector3d n = Eigen::Vector3d(1.0, 2.0, 2.0) / 3.0;
  EXPECT_NEAR(contact_stiffness(-(100.0 + 200.0 + 300.0) * n * n.transpose()), 600.0, 1e-12);
  const Eigen::Vector3d m = Eigen::Vector3d(2.0, -1.0, 0.0).normalized();
  EXPECT_LT(contact_stiffness(-300.0 * n * n.transpose() - 300.0 * m * m.transpose()), 599.0);
}

// §4.7's theorem through the coupling: from equilibrium against multiplane penalty contact
// J = −Σ kᵢ nᵢ nᵢᵀ, move the manipulandum by δ; the (linear) contact makes one step land on the
// new equilibrium, and the change of the rendered force is A δ (eq. 4.35) with spectrum in
// [−1/(1/‖J‖₂ + 1/k_VC), 0] (eq. 4.37 up to its sign: the device pushes back), the bound
// attained.
TEST(StiffnessBound, CouplingRendersAtMostTheBound) {
  const CouplingOptions options = newton_options();
  const double k = options.stiffness;
  const Eigen::Vector3d normals[] = {Eigen::Vector3d(0.0, 0.0, 1.0),
                                     Eigen::Vector3d(0.3, 0.0, 1.0).normalized(),
                                     Eigen::Vector3d(-0.2, 0.5, 1.0).normalized()};
  const double stiffnesses[] = {1000.0, 2000.0, 500.0};
  ContactWrench contact;
  for (int i = 0; i < 3; ++i) {
    contact.force_by_translation -= stiffnesses[i] * normals[i] * normals[i].transpose();
  }
  contact.force = {1.0, -2.0, 6.0};
  const Pose equilibrium = translated(-contact.force / k);  // k_VC (x_m − 0) + F_C = 0
  Eigen::Matrix3d rendered_stiffness;
  const double delta = 1e-3;
  for (int j = 0; j < 3; ++j) {
    VirtualCoupling coupling(options);
    const Pose moved = translated(equilibrium.position + delta * Eigen::Vector3d::Unit(j));
    const CouplingStep step = coupling.step(moved, contact);
    rendered_stiffness.col(j) = (step.rendered.force - contact.force) / delta;
  }
  VirtualCoupling still(options);
  EXPECT_LE(still.step(equilibrium, contact).simulation.position.norm(), 1e-18);

  const double bound = rendered_stiffness_bound(k, contact_stiffness(contact.force_by_translation));
  EXPECT_LT(bound, k);
  EXPECT_LE((rendered_stiffness - rendered_stiffness.transpose()).norm(), 1e-10 * bound);
  const Eigen::Vector3d spectrum =
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(rendered_stiffness).eigenvalues();
  EXPECT_LE(spectrum.maxCoeff(), 1e-10 * bound);
  EXPECT_NEAR(spectrum.minCoeff(), -bound, 1e-10 * bound);

  // ℓ points in parallel (eq. 4.30): along the normal, exactly 1/(1/(ℓ k_C) + 1/k_VC).
  ContactWrench plane;
  plane.force_by_translation = -(10.0 * 1000.0) * normals[1] * normals[1].transpose();
  VirtualCoupling coupling(options);
  const CouplingStep step = coupling.step(translated(delta * normals[1]), plane);
  EXPECT_NEAR(step.rendered.force.dot(normals[1]) / delta,
              -rendered_stiffness_bound(k, 10.0 * 1000.0), 1e-9);
}

// A non-finite manipulandum pose or contact result renders nothing and leaves the simulation
// object where it was; the next good cycle proceeds as usual.
TEST(VirtualCoupling, NonFiniteInputRendersNothing) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  CouplingOptions options = newton_options();
  options.static_damping = 0.5;
  VirtualCoupling coupling(options);
  const Pose good = rotated({0.01, 0.0, 0.0}, 0.2, {0.0, 1.0, 0.0});
  ContactWrench contact;
  contact.force_by_translation = -1000.0 * Eigen::Matrix3d::Identity();
  coupling.step(good, contact);
  const Pose before = coupling.simulation_pose();

  std::vector<std::pair<const char*, std::function<void(Pose&, ContactWrench&)>>> corruptions = {
      {"position", [&](Pose& p, ContactWrench&) { p.position.y() = nan; }},
      {"orientation", [&](Pose& p, ContactWrench&) { p.orientation.x() = unlimited; }},
      {"zero quaternion", [&](Pose& p, ContactWrench&) { p.orientation.coeffs().setZero(); }},
      {"huge quaternion", [&](Pose& p, ContactWrench&) { p.orientation.coeffs().fill(1e300); }},
      {"force", [&](Pose&, ContactWrench& c) { c.force.x() = nan; }},
      {"torque", [&](Pose&, ContactWrench& c) { c.torque.z() = -unlimited; }},
      {"∂F/∂x", [&](Pose&, ContactWrench& c) { c.force_by_translation(1, 2) = nan; }},
      {"∂F/∂ω", [&](Pose&, ContactWrench& c) { c.force_by_rotation(0, 0) = nan; }},
      {"∂T/∂x", [&](Pose&, ContactWrench& c) { c.torque_by_translation(2, 1) = unlimited; }},
      {"∂T/∂ω", [&](Pose&, ContactWrench& c) { c.torque_by_rotation(1, 1) = nan; }},
  };
  for (const auto& [name, corrupt] : corruptions) {
    Pose manipulandum = good;
    ContactWrench bad = contact;
    corrupt(manipulandum, bad);
    const CouplingStep step = coupling.step(manipulandum, bad);
    EXPECT_FALSE(step.valid) << name;
    EXPECT_EQ(step.rendered.force, Eigen::Vector3d::Zero()) << name;
    EXPECT_EQ(step.rendered.torque, Eigen::Vector3d::Zero()) << name;
    EXPECT_EQ(coupling.simulation_pose().position, before.position) << name;
    EXPECT_EQ(coupling.simulation_pose().orientation.coeffs(), before.orientation.coeffs()) << name;
    EXPECT_EQ(step.simulation.position, before.position) << name;
  }
  EXPECT_TRUE(coupling.step(good, contact).valid);

  // Finite input that overflows (x_m − x_s = −∞) is caught the same way.
  ASSERT_TRUE(coupling.reset(translated({1.5e308, 0.0, 0.0})));
  const CouplingStep overflow = coupling.step(translated({-1.5e308, 0.0, 0.0}), contact);
  EXPECT_FALSE(overflow.valid);
  EXPECT_EQ(overflow.rendered.force, Eigen::Vector3d::Zero());
  EXPECT_EQ(coupling.simulation_pose().position.x(), 1.5e308);

  EXPECT_FALSE(coupling.reset({{nan, 0.0, 0.0}, {1.0, 0.0, 0.0, 0.0}}));
  EXPECT_TRUE(coupling.reset({{0.0, 0.0, 0.0}, {2.0, 0.0, 0.0, 0.0}}));
  EXPECT_EQ(coupling.simulation_pose().orientation.w(), 1.0);  // normalized
  EXPECT_TRUE(test::throws_with_message<Error>(
      [&] {
        VirtualCoupling(options, {{0.0, 0.0, 0.0}, {0.0, 0.0, 0.0, 0.0}});
      },
      "starting simulation pose"));
}

// Steps allocate nothing: regular, saturated, degenerate and clamped cycles.
TEST(VirtualCoupling, StepDoesNotAllocate) {
  CouplingOptions options;
  options.saturation_force = 5.0;
  options.object_radius = 0.05;
  options.max_rendered_force = 3.0;
  options.max_rendered_torque = 0.1;
  VirtualCoupling coupling(options);
  ContactWrench contact;
  contact.force_by_translation.diagonal() << 0.0, -2e4, -2e4;
  contact.torque_by_rotation = -50.0 * Eigen::Matrix3d::Identity();
  contact.force = {0.0, 2.0, 0.0};

  test::allocation_count = 0;
  std::vector<double> probe(3);  // the probe counts
  EXPECT_GT(test::allocation_count.load(), 0u);
  probe.clear();

  int valid = 0, degenerate = 0;
  test::allocation_count = 0;
  for (int cycle = 0; cycle < 1000; ++cycle) {
    const double t = 1e-3 * cycle;
    const Pose manipulandum = rotated({std::sin(3.0 * t), 0.01 * t, 0.0}, 4.0 * t, {0, 0, 1});
    const CouplingStep step = coupling.step(manipulandum, contact);
    valid += step.valid ? 1 : 0;
    degenerate += step.degenerate_dimension > 0 ? 1 : 0;
  }
  EXPECT_EQ(test::allocation_count.load(), 0u);
  EXPECT_EQ(valid, 1000);
  EXPECT_GT(degenerate, 0);
}

TEST(CouplingOptions, ValidateNamesTheBadOption) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::vector<std::pair<std::function<void(CouplingOptions&)>, const char*>> cases = {
      {[](CouplingOptions& o) { o.stiffness = 0.0; }, "stiffness must be finite and > 0"},
      {[](CouplingOptions& o) { o.stiffness = unlimited; }, "stiffness must be finite"},
      {[](CouplingOptions& o) { o.torque_stiffness = -1.0; }, "torque_stiffness"},
      {[](CouplingOptions& o) { o.static_damping = 1.0; }, "static_damping"},
      {[&](CouplingOptions& o) { o.static_damping = nan; }, "static_damping"},
      {[](CouplingOptions& o) { o.period = 0.0; }, "period"},
      {[](CouplingOptions& o) { o.max_speed = 0.0; }, "max_speed"},
      {[&](CouplingOptions& o) { o.max_angular_speed = nan; }, "max_angular_speed"},
      {[](CouplingOptions& o) { o.saturation_force = -5.0; }, "saturation_force"},
      {[](CouplingOptions& o) { o.object_radius = 0.0; }, "object_radius"},
      {[](CouplingOptions& o) { o.max_rendered_force = 0.0; }, "max_rendered_force"},
      {[](CouplingOptions& o) { o.max_rendered_torque = 0.0; }, "max_rendered_torque"},
      {[](CouplingOptions& o) { o.device_max_stiffness = 0.0; }, "device_max_stiffness must"},
      {[](CouplingOptions& o) { o.device_max_stiffness = 400.0; },
       "stiffness must be ≤ device_max_stiffness"},
      {[](CouplingOptions& o) { o.degenerate_threshold = 0.0; }, "degenerate_threshold"},
      {[](CouplingOptions& o) { o.degenerate_threshold = 1.0; }, "degenerate_threshold"},
      {[](CouplingOptions& o) { o.rotation_length = unlimited; }, "rotation_length"},
      {[](CouplingOptions& o) { o.rotation_length = -0.1; }, "rotation_length"},
  };
  CouplingOptions defaults;
  EXPECT_NO_THROW(defaults.validate());
  defaults.device_max_stiffness = 600.0;  // the thesis's PHANToM: 0.6 N/mm
  EXPECT_NO_THROW(defaults.validate());
  for (const auto& [change, expected] : cases) {
    CouplingOptions options;
    change(options);
    EXPECT_TRUE(test::throws_with_message<Error>([&] { options.validate(); }, expected));
    EXPECT_TRUE(test::throws_with_message<Error>([&] { VirtualCoupling{options}; }, expected));
  }
}

}  // namespace
}  // namespace khz::haptic
