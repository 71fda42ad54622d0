// The hard cases of the closed haptic loop (thesis §4.6–§4.10): the configurations the thesis
// names as the ones that break static virtual coupling unless speed limits, saturation and the
// degenerate-rank solve do their job. Each runs a one-pair World in simulated time against a
// simulated hand and device (hard_case_fixtures.hpp) and checks, besides the case's own behaviour:
//   - everything finite, every cycle;
//   - no energy growth (device kinetic energy once the hand holds still, or the deformable
//     object's energy after release);
//   - penetration ≤ 1 voxel with saturation on (§4.9: F_VC,max = k_C h/2);
//   - rendered stiffness ≤ k_VC (§4.7), measured at quasi-static equilibrium.
#include "hard_case_fixtures.hpp"

#include <khz/contact/field/implicit_shapes.hpp>
#include <khz/contact/query/contact_query.hpp>
#include <khz/haptic/coupling/saturation.hpp>
#include <khz/haptic/coupling/stiffness_bound.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>

namespace khz::haptic::hard_cases {
namespace {

using contact::HapticObject;

/// Every case runs frictionless, as in the thesis, and with friction μ_s = 0.5, μ_k = 0.4 on its
/// contact (issue 20; rubbings()). With friction a case must stay as stable and safe as without:
/// finite, no step beyond d_max, at most a voxel of penetration, no more stiffness than k_VC, no
/// energy gained once the hand holds still. What only frictionless contact does (a peg sliding
/// freely along its shaft, a box snapping in its plane, a ball turning freely in its socket) is
/// checked without friction only.
class HapticHardCases : public RubbingCases {};

INSTANTIATE_TEST_SUITE_P(, HapticHardCases, ::testing::ValuesIn(rubbings()), RubbingName());

/// d_max of §4.6 with the shared options (m per cycle), and the relative slack of a length the
/// coupling clamped to it (one rounding of the clamp's scaling).
double max_step() { return coupling_options(1.0).max_translation_per_cycle(); }
constexpr double round_off = 1e-12;

/// The device's kinetic energy does not grow while the hand holds still: its peak over the last
/// `window` cycles of the trace is no larger than over the `window` before, and below `floor`
/// (J), the energy of a device that has come to rest (1 µJ: 0.45 kg at 2 mm/s).
void expect_settled(const std::vector<Sample>& trace, std::size_t window, double floor = 1e-6) {
  const std::size_t end = trace.size();
  const auto energy = [](const Sample& s) { return s.device_energy; };
  const double earlier = largest(trace, end - 2 * window, end - window, energy);
  const double late = largest(trace, end - window, end, energy);
  EXPECT_LE(late, earlier) << "the device gained energy while the hand held still";
  EXPECT_LT(late, floor);
}

/// What every case ends with: at most a voxel of penetration in any cycle (§4.9), a rendered
/// stiffness at the final pose along `direction` no larger than k_VC (§4.7), and no energy growth
/// while the hand holds still.
void expect_safe_ending(Harness& run, const Eigen::Vector3d& direction) {
  const std::vector<Sample>& trace = run.trace();
  EXPECT_LE(largest(trace, 0, trace.size(), [](const Sample& s) { return s.penetration; }), voxel);
  EXPECT_LE(quasi_static_stiffness(run.coupling(), run.world(), trace.back().record.manipulandum,
                                   direction, 1e-4),
            coupling_stiffness * (1.0 + 1e-6));
  expect_settled(trace, 300);
}

// ---------------------------------------------------------------------------------------------
// 1. Free-space fast motion into saturation (§4.10's first example).

TEST_P(HapticHardCases, FastMotionInFreeSpaceSnapsThroughTheSaturatedCouplingWithoutExploding) {
  // A 3 cm ball held in free space (the floor is a metre away). The hand's anchor jumps 20 cm in
  // 20 ms and back: the device reaches several m/s, far beyond the 0.6 m/s the simulation object
  // may move (§4.6), so the coupling stretches deep into saturation, where its radial gradient
  // vanishes (eq. 4.40) and the 6×6 system loses rank: §4.10 snaps along the degenerate
  // direction, and the speed limit bounds the snap to d_max per cycle.
  const contact::PointTree ball = nested_tree(sphere_pointshell(0.03, 85 * 16), 85);
  const contact::ImplicitShape floor = contact::HalfSpace(Eigen::Vector3d::UnitZ(), -1.0);
  const PairScene scene(ball, floor, analytic_options(HapticObject::pointshell),
                        Eigen::Vector3d::Zero(), Eigen::Isometry3d::Identity());
  const Eigen::Vector3d far(0.15, 0.1, 0.05);
  const CouplingOptions options = coupling_options(0.03);
  Harness run(keyframe_target({{0.0, at(Eigen::Vector3d::Zero())},
                               {0.1, at(Eigen::Vector3d::Zero())},
                               {0.12, at(far)},
                               {0.6, at(far)},
                               {0.62, at(Eigen::Vector3d::Zero())}}),
              scene, options);
  run.run(2500);
  const std::vector<Sample>& trace = run.trace();
  ASSERT_EQ(first_non_finite(trace), trace.size());

  int degenerate = 0, saturated_snaps = 0;
  double widest = 0.0;
  for (std::size_t i = 1; i < trace.size(); ++i) {
    const CycleRecord& r = trace[i].record;
    const Pose& before = trace[i - 1].record.simulation;
    ASSERT_TRUE(r.device_valid && r.contact_valid && r.coupling_valid) << "cycle " << i;
    ASSERT_EQ(r.contact.statistics.points_in_contact, 0) << "free space";
    const Eigen::Vector3d moved = r.simulation.position - before.position;
    const Eigen::Vector3d gap = r.manipulandum.position - before.position;
    widest = std::max(widest, gap.norm());
    // §4.6: never more than d_max per cycle, whatever the solve produced.
    ASSERT_LE(moved.norm(), max_step() * (1.0 + round_off)) << "cycle " << i;
    if (r.degenerate_dimension >= 1) {
      ++degenerate;
      // The snap of eq. 4.41 moves towards the manipulandum; (1 − α) of a gap of more than
      // 2 d_max is beyond the limit, so the object moves exactly d_max straight at it.
      if (gap.norm() > 2.0 * max_step() / (1.0 - options.static_damping)) {
        ++saturated_snaps;
        EXPECT_NEAR(moved.dot(gap.normalized()), max_step(), 1e-9 * max_step()) << "cycle " << i;
      }
    }
  }
  // The stretch went far beyond r_lin = F_VC,max / (2 k_VC) = 2 mm, and the system went
  // degenerate there.
  EXPECT_GT(widest, 20.0 * saturation_force / (2.0 * coupling_stiffness));
  EXPECT_GT(saturated_snaps, 10);
  EXPECT_GE(degenerate, saturated_snaps);
  // The rendered force is the unsaturated −k_VC (x_m − x_s), clamped to the device's 8.5 N.
  EXPECT_LE(largest(trace, 0, trace.size(),
                    [](const Sample& s) { return s.record.rendered.force.norm(); }),
            options.max_rendered_force * (1.0 + round_off));

  // The hand holds still at the start again: the object has caught up exactly (each free-space
  // cycle halves the gap, α = 0.5), the device is at rest, and in free space the rendered
  // stiffness is zero.
  const CycleRecord& last = trace.back().record;
  EXPECT_LT((last.simulation.position - last.manipulandum.position).norm(), 1e-9);
  expect_settled(trace, 300);
  EXPECT_LT(quasi_static_stiffness(run.coupling(), run.world(), last.manipulandum,
                                   Eigen::Vector3d::UnitX(), 1e-4),
            1e-6);
}

// ---------------------------------------------------------------------------------------------
// 2. Square peg in a square shaft (§4.10's 1-D degeneracy).

/// The solid around an infinite square shaft along z of half width `a`: the union of the four
/// half-spaces beyond its walls (exact inside the shaft, where the peg is).
contact::ImplicitUnion square_shaft(double a) {
  std::vector<contact::ImplicitShape> walls;
  for (int axis = 0; axis < 2; ++axis) {
    for (const double side : {-1.0, 1.0}) {
      walls.emplace_back(contact::HalfSpace(-side * Eigen::Vector3d::Unit(axis), -a));
    }
  }
  return contact::ImplicitUnion(std::move(walls));
}

/// Case 2's hand: it throws the peg 8 cm up its shaft in 0.1 s, 16 cm down in 50 ms, back, then
/// pushes it into the +x wall.
TargetFunction peg_in_shaft_script() {
  return keyframe_target({{0.0, at(Eigen::Vector3d::Zero())},
                          {0.1, at(Eigen::Vector3d::Zero())},
                          {0.2, at({0.0, 0.0, 0.08})},
                          {0.6, at({0.0, 0.0, 0.08})},
                          {0.65, at({0.0, 0.0, -0.08})},
                          {1.0, at({0.0, 0.0, -0.08})},
                          {1.1, at(Eigen::Vector3d::Zero())},
                          {1.6, at(Eigen::Vector3d::Zero())},
                          {1.7, at({0.03, 0.0, 0.0})}});
}

/// Unwrapped rotation angles about `axis` (rad): the sum of the per-cycle turns, so 270° is
/// 4.71 rad and not −1.57.
std::vector<double> unwrapped_angles(const std::vector<Sample>& trace, const Eigen::Vector3d& axis,
                                     bool simulation) {
  std::vector<double> angles(trace.size(), 0.0);
  for (std::size_t i = 1; i < trace.size(); ++i) {
    const auto orientation = [&](std::size_t j) {
      return simulation ? trace[j].record.simulation.orientation
                        : trace[j].record.manipulandum.orientation;
    };
    const Eigen::AngleAxisd turn(orientation(i) * orientation(i - 1).conjugate());
    double angle = turn.angle();
    if (angle > std::numbers::pi) angle -= 2.0 * std::numbers::pi;
    angles[i] = angles[i - 1] + angle * turn.axis().dot(axis);
  }
  return angles;
}

TEST_P(HapticHardCases, APegMovedFastAlongItsShaftSlidesWithItAndCannotLeaveSideways) {
  // A 2 × 2 × 6 cm peg (896 points) in a square shaft 0.5 mm narrower, so all four walls touch
  // (0.25 mm each): the contact resists x, y and every rotation, never motion along z. The hand
  // throws it 8 cm up the shaft in 0.1 s, 16 cm down in 50 ms, back, then pushes it into the
  // +x wall with 9 N.
  const Eigen::Vector3d half(0.01, 0.01, 0.03);
  const contact::PointTree peg =
      nested_tree(box_pointshell(Eigen::Vector3d::Zero(), half, 2.5e-3), 14);
  constexpr double interference = 2.5e-4;
  const contact::ImplicitUnion shaft = square_shaft(half.x() - interference);
  const PairScene scene(peg, shaft, analytic_options(HapticObject::pointshell),
                        Eigen::Vector3d::Zero(), Eigen::Isometry3d::Identity());
  const CouplingOptions options = coupling_options(half.norm());
  Harness run(peg_in_shaft_script(), scene, options, [&](const Pose& grasp) {
    return deepest_penetration(peg.pointshell().points, shaft,
                               held_body_pose(grasp, Eigen::Vector3d::Zero()));
  });
  run.run(1600);
  // Along the shaft nothing resists: the quasi-static rendered stiffness along z is zero.
  const double along =
      quasi_static_stiffness(run.coupling(), run.world(), run.trace().back().record.manipulandum,
                             Eigen::Vector3d::UnitZ(), 1e-3);
  run.run(1400);
  const std::vector<Sample>& trace = run.trace();
  ASSERT_EQ(first_non_finite(trace), trace.size());

  int snaps = 0;
  double lateral = 0.0;
  for (std::size_t i = 1; i < 1600; ++i) {
    const CycleRecord& r = trace[i].record;
    const Pose& before = trace[i - 1].record.simulation;
    ASSERT_TRUE(r.device_valid && r.contact_valid && r.coupling_valid) << "cycle " << i;
    ASSERT_LE((r.simulation.position - before.position).norm(), max_step() * (1.0 + round_off));
    // Moving along the shaft faster than the object may (lag beyond a few r_lin): the
    // saturated coupling leaves the shaft's direction degenerate, and the object snaps along it.
    const double gap = r.manipulandum.position.z() - before.position.z();
    if (!frictionless()) {
      // Clamped: the walls' friction, μ_s L k_C × 0.25 mm = 2.5 N, holds more than the saturated
      // coupling's 2 N pulls, so the peg stays where it is along the shaft.
      EXPECT_LT(std::abs(r.simulation.position.z()), 1e-3) << "cycle " << i;
    } else if (std::abs(gap) > 10.0 * saturation_force / (2.0 * coupling_stiffness)) {
      EXPECT_GE(r.degenerate_dimension, 1) << "cycle " << i;
      EXPECT_NEAR(std::abs(r.simulation.position.z() - before.position.z()), max_step(),
                  1e-6 * max_step())
          << "cycle " << i;
      ++snaps;
    } else if (std::abs(gap) < max_step()) {
      // Otherwise along z it follows the static-damping law of §4.8 exactly: nothing but the
      // coupling acts along the shaft, so each cycle closes (1 − α) of the gap.
      EXPECT_NEAR(r.simulation.position.z() - before.position.z(),
                  (1.0 - options.static_damping) * gap, 1e-9)
          << "cycle " << i;
    }
    lateral = std::max(lateral, r.simulation.position.head<2>().norm());
  }
  // Sideways the walls hold it: it moves no further than the penetration allows.
  EXPECT_LE(lateral, voxel);
  // Pushed into the wall: held within a voxel, while the device is a centimetre inside, the
  // contact force below F_VC,max.
  const Sample& last = trace.back();
  EXPECT_GT(last.record.manipulandum.position.x(), 0.01);
  EXPECT_LE(last.record.simulation.position.x(), voxel);
  EXPECT_LT(-last.record.contact.force.x(), saturation_force);
  if (frictionless()) {
    EXPECT_GT(snaps, 50);
    EXPECT_LT(along, 1e-6);
    // At rest the contact balances the saturated coupling force, eq. 4.39 of the spring
    // rendered to the device, and nothing holds the peg along the shaft.
    EXPECT_NEAR(-last.record.contact.force.x(),
                saturation_profile(last.record.rendered.force.norm(), saturation_force), 1e-6);
    EXPECT_NEAR(last.record.simulation.position.z(), last.record.manipulandum.position.z(), 1e-6);
  }
  expect_safe_ending(run, Eigen::Vector3d::UnitX());
}

// ---------------------------------------------------------------------------------------------
// 3. A box between two parallel planes (§4.10's 2-D degeneracy).

TEST_P(HapticHardCases, ABoxSqueezedBetweenTwoPlanesFollowsFastInPlaneMotion) {
  // A 4 × 4 × 2 cm box (768 points) between two planes 0.5 mm closer than its height: the
  // contact resists z and the tilts, not x, y or the turn about z. The hand throws it 15 cm
  // diagonally in 30 ms and back.
  const Eigen::Vector3d half(0.02, 0.02, 0.01);
  const contact::PointTree box =
      nested_tree(box_pointshell(Eigen::Vector3d::Zero(), half, 2.5e-3), 12);
  constexpr double interference = 2.5e-4;
  const double a = half.z() - interference;
  const contact::ImplicitUnion planes(
      {contact::ImplicitShape(contact::HalfSpace(Eigen::Vector3d::UnitZ(), -a)),
       contact::ImplicitShape(contact::HalfSpace(-Eigen::Vector3d::UnitZ(), -a))});
  const PairScene scene(box, planes, analytic_options(HapticObject::pointshell),
                        Eigen::Vector3d::Zero(), Eigen::Isometry3d::Identity());
  const CouplingOptions options = coupling_options(half.norm());
  const Eigen::Vector3d far(0.1, 0.1, 0.0);
  Harness run(keyframe_target({{0.0, at(Eigen::Vector3d::Zero())},
                               {0.1, at(Eigen::Vector3d::Zero())},
                               {0.13, at(far)},
                               {0.7, at(far)},
                               {0.73, at(Eigen::Vector3d::Zero())}}),
              scene, options, [&](const Pose& grasp) {
                return deepest_penetration(box.pointshell().points, planes,
                                           held_body_pose(grasp, Eigen::Vector3d::Zero()));
              });
  run.run(frictionless() ? 2000 : 3000);  // with friction it settles more slowly
  const std::vector<Sample>& trace = run.trace();
  ASSERT_EQ(first_non_finite(trace), trace.size());
  int two_dimensional = 0;
  double height = 0.0;
  for (std::size_t i = 1; i < trace.size(); ++i) {
    const CycleRecord& r = trace[i].record;
    const Pose& before = trace[i - 1].record.simulation;
    ASSERT_TRUE(r.device_valid && r.contact_valid && r.coupling_valid) << "cycle " << i;
    ASSERT_LE((r.simulation.position - before.position).norm(), max_step() * (1.0 + round_off));
    if (r.degenerate_dimension >= 2) ++two_dimensional;
    height = std::max(height, std::abs(r.simulation.position.z()));
  }
  // The thrown box lags its hand by more than F_VC,max / (ε σ₁): then neither in-plane direction
  // keeps a coupling stiffness above ε σ₁ (σ₁ ≈ L k_C, the planes), the 2-D null space of the
  // contact is degenerate, and the box snaps in the plane.
  EXPECT_LE(height, voxel);
  const CycleRecord& last = trace.back().record;
  if (frictionless()) {
    EXPECT_GT(two_dimensional, 10);
    EXPECT_EQ(last.degenerate_dimension, 0) << "at rest the unsaturated coupling regularizes";
    EXPECT_LT((last.simulation.position - last.manipulandum.position).head<2>().norm(), 1e-6);
    EXPECT_LT(quasi_static_stiffness(run.coupling(), run.world(), last.manipulandum,
                                     Eigen::Vector3d(1.0, 1.0, 0.0), 1e-3),
              1e-6);
  } else {
    // Clamped between the planes as the peg in its shaft: it stays where it was.
    EXPECT_LT(last.simulation.position.head<2>().norm(), 1e-3);
  }
  expect_safe_ending(run, Eigen::Vector3d::UnitZ());
}

// ---------------------------------------------------------------------------------------------
// 4. A ball in a hemispherical socket (§4.10's 3-D torque degeneracy).

TEST_P(HapticHardCases, ABallTurnedFastInItsSocketFollowsTheHandAndStaysSeated) {
  // A 2 cm ball (1,360 points) pressed with 3 N into a socket carved from a floor, 0.25 mm
  // tighter than the ball, the field sampled on a 2 mm grid. Every contact force points at the
  // centre, so the contact has no torque and no torque gradient: only the coupling decides the
  // ball's orientation. The hand turns it 90° about x in 50 ms (31 rad/s, five times the
  // angular speed limit) and back.
  constexpr double radius = 0.02, interference = 2.5e-4;
  const contact::PointTree ball = nested_tree(sphere_pointshell(radius, 85 * 16), 85);
  const contact::DistanceGrid socket = sampled_field(
      [&](const Eigen::Vector3d& p) { return std::max(p.z(), radius - interference - p.norm()); },
      voxel_grid(Eigen::Vector3d::Constant(-0.04), Eigen::Vector3d::Constant(0.04)));
  const PairScene scene(ball, socket, options(HapticObject::pointshell), Eigen::Vector3d::Zero(),
                        Eigen::Isometry3d::Identity());
  const CouplingOptions options = coupling_options(radius);
  const HandModel hand;
  const Eigen::Vector3d pressed(0.0, 0.0, -3.0 / hand.stiffness - 3.0 / coupling_stiffness);
  const Eigen::Quaterniond quarter = turned(std::numbers::pi / 2.0, Eigen::Vector3d::UnitX());
  Harness run(keyframe_target({{0.0, at(Eigen::Vector3d::Zero())},
                               {0.3, at(pressed)},
                               {0.5, at(pressed)},
                               {0.55, at(pressed, quarter)},
                               {1.0, at(pressed, quarter)},
                               {1.05, at(pressed)}}),
              scene, options, [&](const Pose& grasp) {
                return deepest_penetration(ball.pointshell().points, socket,
                                           held_body_pose(grasp, Eigen::Vector3d::Zero()));
              });
  // With friction the ball settles more slowly: a second more of holding still.
  const int cycles = frictionless() ? 2000 : 3000;
  double torque_gradient = 0.0;
  for (int i = 0; i < cycles; ++i) {
    run.step();
    torque_gradient =
        std::max(torque_gradient, run.world().pair_result(0).torque_by_rotation.norm());
  }
  const std::vector<Sample>& trace = run.trace();
  ASSERT_EQ(first_non_finite(trace), trace.size());
  int snaps = 0;
  double off_centre = 0.0;
  const double max_turn = options.max_rotation_per_cycle();
  for (std::size_t i = 1; i < trace.size(); ++i) {
    const CycleRecord& r = trace[i].record;
    const Pose& before = trace[i - 1].record.simulation;
    ASSERT_TRUE(r.device_valid && r.contact_valid && r.coupling_valid) << "cycle " << i;
    const double turn = r.simulation.orientation.angularDistance(before.orientation);
    const double gap = r.manipulandum.orientation.angularDistance(before.orientation);
    ASSERT_LE(turn, max_turn * (1.0 + 1e-9)) << "cycle " << i;
    // Turned faster than it may (§4.6): the ball turns by θ_max a cycle. Far enough behind, the
    // coupling torque saturates (plateau F_VC,max × radius, linear to half of it: 2.3°) until its
    // radial direction is degenerate, and the ball snaps.
    if (frictionless() && gap > 2.0 * max_turn / (1.0 - options.static_damping)) {
      EXPECT_NEAR(turn, max_turn, 1e-6 * max_turn) << "cycle " << i;
      if (r.degenerate_dimension >= 1) ++snaps;
    }
    if (i > 300) off_centre = std::max(off_centre, r.simulation.position.norm());
  }
  if (frictionless()) {
    // Seated: the centre never leaves the socket's by more than the penetration allows.
    EXPECT_LE(off_centre, voxel);
    EXPECT_GT(snaps, 50);
    // The contact offers no torque resistance (3-D torque degeneracy, up to the grid's gradient
    // noise), compared with the coupling's ½ k_VC,torque.
    EXPECT_LT(torque_gradient, 1e-3 * options.torque_stiffness / 2.0);
    const CycleRecord& last = trace.back().record;
    EXPECT_LT(last.simulation.orientation.angularDistance(last.manipulandum.orientation), 1e-6);
  }
  // With friction the turning ball rolls partly up the socket's wall (its points' friction
  // pushes it sideways with more than the saturated coupling holds it) and comes to rest there,
  // held by friction: in the socket, less than half its radius off centre, not on the rim
  // (a radius off).
  EXPECT_LE(trace.back().record.simulation.position.norm(), frictionless() ? voxel : radius / 2);
  std::printf("ball in its socket: %.2f mm off centre at most, %.2f mm at the end\n",
              1e3 * off_centre, 1e3 * trace.back().record.simulation.position.norm());
  expect_safe_ending(run, -Eigen::Vector3d::UnitZ());
}

// ---------------------------------------------------------------------------------------------
// 5. The manipulandum turned 180° and beyond (eq. 4.15's positive hemisphere).

TEST_P(HapticHardCases, TurningPastAHalfTurnTurnsTheObjectTheShortWayWithoutATorqueJump) {
  // A 4 × 4 × 2 cm box resting with 1 N on a floor, turned by the hand about the vertical by
  // 450° at 300°/s (keyframes every 90°, below the 360°/s limit). The device's quaternion
  // crosses into the negative hemisphere at 180° and back at 540°.
  const Eigen::Vector3d half(0.02, 0.02, 0.01);
  const contact::PointTree box =
      nested_tree(box_pointshell(Eigen::Vector3d::Zero(), half, 2.5e-3), 12);
  const contact::ImplicitShape floor = contact::HalfSpace(Eigen::Vector3d::UnitZ(), 0.0);
  const PairScene scene(box, floor, analytic_options(HapticObject::pointshell),
                        Eigen::Vector3d::Zero(), Eigen::Isometry3d::Identity());
  const CouplingOptions options = coupling_options(half.norm());
  const HandModel hand;
  const Eigen::Vector3d rest(0.0, 0.0, half.z() - 1.0 / hand.stiffness - 1.0 / coupling_stiffness);
  std::vector<Keyframe> keys = {{0.0, at({0.0, 0.0, 0.015})}, {0.3, at(rest)}};
  for (int quarter = 1; quarter <= 5; ++quarter) {
    keys.push_back({0.3 + 0.3 * quarter,
                    at(rest, turned(quarter * std::numbers::pi / 2.0, Eigen::Vector3d::UnitZ()))});
  }
  Harness run(keyframe_target(keys), scene, options, [&](const Pose& grasp) {
    return deepest_penetration(box.pointshell().points, floor,
                               held_body_pose(grasp, Eigen::Vector3d::Zero()));
  });
  run.run(2600);
  const std::vector<Sample>& trace = run.trace();
  ASSERT_EQ(first_non_finite(trace), trace.size());
  const std::vector<double> device = unwrapped_angles(trace, Eigen::Vector3d::UnitZ(), false);
  const std::vector<double> object = unwrapped_angles(trace, Eigen::Vector3d::UnitZ(), true);
  int crossings = 0;
  double lag = 0.0;
  for (std::size_t i = 1; i < trace.size(); ++i) {
    const CycleRecord& r = trace[i].record;
    const CycleRecord& p = trace[i - 1].record;
    ASSERT_TRUE(r.device_valid && r.contact_valid && r.coupling_valid) << "cycle " << i;
    // No jump: the rendered torque k_VC,torque vector(q_m q_s⁻¹) changes by at most
    // ½ k_VC,torque per radian that either side turned (|d vector(q)| ≤ ½ dθ).
    const double turned_by =
        std::abs(device[i] - device[i - 1]) + std::abs(object[i] - object[i - 1]);
    EXPECT_LE((r.rendered.torque - p.rendered.torque).norm(),
              0.5 * options.torque_stiffness * turned_by * (1.0 + 1e-6) + 1e-12)
        << "cycle " << i;
    // While the hand turns steadily (between 90° and 360° of its way), the object lags and the
    // rendered torque holds the device back: its sign never flips, across 180° too.
    if (device[i] > std::numbers::pi / 2.0 && device[i] < 2.0 * std::numbers::pi) {
      EXPECT_LT(r.rendered.torque.z(), 0.0) << "cycle " << i;
      if (r.manipulandum.orientation.w() * p.manipulandum.orientation.w() <= 0.0) ++crossings;
    }
    // The object turns the short way: it stays within the lag of the device's angle.
    EXPECT_LT(std::abs(object[i] - device[i]), 0.1) << "cycle " << i;
    lag = std::max(lag, std::abs(object[i] - device[i]));
  }
  EXPECT_GE(crossings, 1) << "the device's quaternion crossed the hemisphere border";
  // With friction the object stops where the coupling's torque no longer overcomes the floor's
  // friction: a little short (measured: 2.4 mrad).
  EXPECT_NEAR(object.back(), 2.5 * std::numbers::pi, frictionless() ? 1e-3 : 1e-2);
  std::printf("half turn: the object lagged the device by %.3f rad at most, %.4f at the end\n", lag,
              2.5 * std::numbers::pi - object.back());
  EXPECT_NEAR(device.back(), 2.5 * std::numbers::pi, 1e-3);
  expect_safe_ending(run, -Eigen::Vector3d::UnitZ());
}

// ---------------------------------------------------------------------------------------------
// 6. A long rod levered against a thin pillar (§4.9's torque saturation).

TEST_P(HapticHardCases, ARodLeveredAgainstAPillarIsHeldByTheSizeAwareTorqueSaturation) {
  // A 20 cm rod of 1 cm section (1,312 points) held at its middle; a 4 mm pillar stands 4 mm
  // beside its +x end. The hand turns the rod 20° about z into the pillar and holds: the end
  // stops after 2.5°, and the coupling torque, k_VC,torque sin(θ/2) = 0.35 N·m unsaturated with
  // k_VC,torque = 2 N·m, saturates to F_VC,max × object_radius = 0.2 N·m, which the pillar meets
  // at the 9 cm lever with ≈ F_VC,max: the end goes no deeper than the force limit allows.
  const Eigen::Vector3d half(0.1, 0.005, 0.005);
  const contact::PointTree rod =
      nested_tree(box_pointshell(Eigen::Vector3d::Zero(), half, 2.5e-3), 20);
  const contact::ImplicitShape pillar = contact::Cylinder(
      Eigen::Vector3d(0.09, 0.013, -0.05), Eigen::Vector3d(0.09, 0.013, 0.05), 0.004);
  const PairScene scene(rod, pillar, analytic_options(HapticObject::pointshell),
                        Eigen::Vector3d::Zero(), Eigen::Isometry3d::Identity());
  CouplingOptions options = coupling_options(half.norm());
  options.torque_stiffness = 2.0;
  const double plateau = options.springs().saturation_torque;
  Harness run(
      keyframe_target({{0.0, at(Eigen::Vector3d::Zero())},
                       {0.1, at(Eigen::Vector3d::Zero())},
                       {0.3, at(Eigen::Vector3d::Zero(), turned(20.0 * std::numbers::pi / 180.0,
                                                                Eigen::Vector3d::UnitZ()))}}),
      scene, options, [&](const Pose& grasp) {
        return deepest_penetration(rod.pointshell().points, pillar,
                                   held_body_pose(grasp, Eigen::Vector3d::Zero()));
      });
  run.run(2000);
  const std::vector<Sample>& trace = run.trace();
  ASSERT_EQ(first_non_finite(trace), trace.size());
  for (const Sample& s : trace) {
    ASSERT_TRUE(s.record.device_valid && s.record.contact_valid && s.record.coupling_valid);
  }
  const CycleRecord& last = trace.back().record;
  // Never through: in the rod's frame the pillar's axis stays beyond the rod's +y side.
  for (const Sample& s : trace) {
    const Eigen::Vector3d axis =
        held_body_pose(s.record.simulation, Eigen::Vector3d::Zero()).inverse() *
        Eigen::Vector3d(0.09, 0.013, 0.0);
    ASSERT_GT(axis.y(), half.y());
  }
  EXPECT_GT(std::abs(last.contact.torque.z()), 0.5 * plateau) << "levered against the pillar";
  // At rest the contact torque balances the saturated coupling torque (eq. 4.39 applied to the
  // unsaturated torque rendered to the device), below its plateau.
  const double rendered = last.rendered.torque.norm();
  EXPECT_NEAR(std::abs(last.contact.torque.z()), saturation_profile(rendered, plateau), 1e-6);
  EXPECT_LT(std::abs(last.contact.torque.z()), plateau);
  EXPECT_LE(rendered, options.max_rendered_torque);
  expect_safe_ending(run, Eigen::Vector3d::UnitY());
}

// ---------------------------------------------------------------------------------------------
// 7. Many simultaneous contacts (§3.5's L/ℓ, §4.7).

/// The cases' contact onset δ (m): the default's on their fields' voxel.
const double case_onset = contact::ContactOptions{}.onset_depth_for(voxel);

/// The depth (m) at which a flat face of many points pressed uniformly with `force` (N) rests
/// on the floor once its count ℓ exceeds L, through the onset δ: each point pushes with
/// k_C d²/(2δ) and counts d/δ within δ, so the face pushes with L k_C d/2 there and with
/// L k_C (d − δ/2) beyond (contact::ContactOptions::onset_depth).
double uniform_press_depth(double force) {
  const double stiffness = scaling_count * point_stiffness;
  return 2.0 * force / stiffness <= case_onset ? 2.0 * force / stiffness
                                               : force / stiffness + case_onset / 2.0;
}

/// That face's contact stiffness (N/m) at depth d (m): L k_C / 2 within the onset, L k_C beyond.
double uniform_press_stiffness(double depth) {
  return scaling_count * point_stiffness * (depth < case_onset ? 0.5 : 1.0);
}

TEST_P(HapticHardCases, HundredsOfContactsKeepTheRenderedStiffnessBelowTheCoupling) {
  // A 6 × 6 × 2 cm box (1,920 points, 576 on its bottom face) lowered flat onto a floor sampled
  // on a 2 mm grid: the whole bottom face touches at once. Without L/ℓ the contact stiffness
  // would be ℓ k_C ≈ 1.2 MN/m; with it ‖∂F/∂x‖₂ ≤ L k_C (the theorem of §4.7 with every point's
  // stiffness scaled by L/ℓ), and the device feels k_VC in series with it (eq. 4.31).
  const Eigen::Vector3d half(0.03, 0.03, 0.01);
  const contact::Pointshell flat = box_pointshell(Eigen::Vector3d::Zero(), half, 2.5e-3);
  const contact::PointTree box = nested_tree(flat, 30);
  const contact::DistanceGrid floor = sampled_field(
      contact::HalfSpace(Eigen::Vector3d::UnitZ(), 0.0),
      voxel_grid(Eigen::Vector3d(-0.05, -0.05, -0.02), Eigen::Vector3d(0.05, 0.05, 0.08)));
  const PairScene scene(box, floor, options(HapticObject::pointshell), Eigen::Vector3d::Zero(),
                        Eigen::Isometry3d::Identity());
  const CouplingOptions options = coupling_options(half.norm());
  const HandModel hand;
  // Phase 1 (to 1.5 s): a gentle press, 0.7 N, in the coupling's linear part (< F_VC,max / 2):
  // the anchor sits 0.7 N / k_h + 0.7 N / k_VC below the resting grasp height h_z. Phase 2: a
  // hard press, the anchor 3 cm lower (9 N of hand force, beyond the saturation).
  const double gentle = 0.7;
  const double resting = half.z() - uniform_press_depth(gentle);
  const double light = resting - gentle / hand.stiffness - gentle / coupling_stiffness;
  Harness run(keyframe_target({{0.0, at({0.0, 0.0, 0.02})},
                               {0.3, at({0.0, 0.0, light})},
                               {1.5, at({0.0, 0.0, light})},
                               {1.6, at({0.0, 0.0, light - 0.03})}}),
              scene, options, [&](const Pose& grasp) {
                return deepest_penetration(box.pointshell().points, floor,
                                           held_body_pose(grasp, Eigen::Vector3d::Zero()));
              });
  // ‖∂F/∂x‖₂ of every cycle's query (the world keeps the last one).
  double stiffest = 0.0;
  const auto run_and_watch = [&](int cycles) {
    for (int i = 0; i < cycles; ++i) {
      run.step();
      stiffest =
          std::max(stiffest, contact_stiffness(run.world().pair_result(0).force_by_translation));
    }
  };
  run_and_watch(1500);
  const Sample gentle_state = run.trace().back();
  const double gentle_stiffness =
      quasi_static_stiffness(run.coupling(), run.world(), gentle_state.record.manipulandum,
                             -Eigen::Vector3d::UnitZ(), 1e-4);
  expect_settled(run.trace(), 300);
  run_and_watch(1500);
  const std::vector<Sample>& trace = run.trace();
  ASSERT_EQ(first_non_finite(trace), trace.size());

  // Hundreds of points in contact, the contact stiffness bounded by L k_C every cycle (the
  // floor's grid gradient is the plane's normal to float rounding).
  EXPECT_GE(gentle_state.record.contact.statistics.points_in_contact, 500);
  EXPECT_GE(trace.back().record.contact.statistics.points_in_contact, 500);
  EXPECT_LE(stiffest, scaling_count * point_stiffness * (1.0 + 1e-6));
  // The gentle press rests where the hand's force balances: 0.7 N on the floor.
  EXPECT_NEAR(gentle_state.record.contact.force.z(), gentle, 0.01 * gentle);
  // §4.7: at the gentle press's equilibrium the device feels k_VC in series with ‖J‖₂, the
  // face's contact stiffness (all normals equal: the theorem's equality case; L k_C / 2 within
  // the onset, where this press rests: 476.2 N/m), below k_VC.
  const double series = rendered_stiffness_bound(
      coupling_stiffness, uniform_press_stiffness(uniform_press_depth(gentle)));
  EXPECT_NEAR(gentle_stiffness, series, 0.01 * series);
  EXPECT_LE(gentle_stiffness, coupling_stiffness);
  // Hard press: the coupling saturates at F_VC,max, the simulation object stops, and the device
  // feels exactly the coupling spring k_VC (no more), until the device's force limit.
  const Sample& hard = trace.back();
  const double hard_stiffness = quasi_static_stiffness(
      run.coupling(), run.world(), hard.record.manipulandum, -Eigen::Vector3d::UnitZ(), 1e-4);
  EXPECT_LE(hard_stiffness, coupling_stiffness * (1.0 + 1e-6));
  EXPECT_LE(hard.record.contact.force.norm(), saturation_force);
  // Penetration: at rest F_VC,max over ≥ L points sinks the face F_VC,max / (L k_C) = h/20
  // under eq. 3.1, 2 F_VC,max / (L k_C) = h/10 through the onset; at most 1 voxel in any cycle.
  const double deepest =
      largest(trace, 0, trace.size(), [](const Sample& s) { return s.penetration; });
  EXPECT_LE(deepest, voxel);
  EXPECT_LE(hard.penetration, uniform_press_depth(saturation_force) * 1.01);
  expect_settled(trace, 300);
}

// ---------------------------------------------------------------------------------------------
// 9. Device faults mid-contact (docs/DEVICES.md, SafeDevice).

/// Cases 9 and 10: a 3 cm ball (1,360 points) held as the pointshell above a floor, and the
/// anchor height at which the hand presses it down with 3 N through the saturated coupling.
struct BallOnFloor {
  /// `options`: the contact's (the held object must be the pointshell).
  explicit BallOnFloor(const contact::ContactOptions& options)
      : scene(ball, floor, options, Eigen::Vector3d::Zero(), Eigen::Isometry3d::Identity()) {}

  static constexpr double radius = 0.03;
  const contact::PointTree ball = nested_tree(sphere_pointshell(radius, 85 * 16), 85);
  const contact::ImplicitShape floor = contact::HalfSpace(Eigen::Vector3d::UnitZ(), 0.0);
  const PairScene scene;
  const double pressed = radius - 3.0 / HandModel{}.stiffness - 3.0 / coupling_stiffness;

  /// The Harness's penetration measure: the ball's deepest point under the floor.
  std::function<double(const Pose&)> penetration() const {
    return [this](const Pose& grasp) {
      return deepest_penetration(ball.pointshell().points, floor,
                                 held_body_pose(grasp, Eigen::Vector3d::Zero()));
    };
  }
};

TEST_P(HapticHardCases, ANaNPoseOrADisconnectMidContactRendersZeroAtOnceAndRecovers) {
  // A 3 cm ball pressed onto a floor with 3 N of hand force (the coupling saturated). At 1.0 s
  // the device reports NaN positions for 5 reads, at 1.6 s it disconnects for 5 reads. The hand
  // keeps pushing through both, so the device sinks while nothing is rendered.
  const BallOnFloor b(analytic_options(HapticObject::pointshell));
  const double radius = BallOnFloor::radius, pressed = b.pressed;
  SafetyOptions safety;
  safety.ramp_cycles = 20;
  // This case is about the ramp: the hand never eases off, which the wait for a small force
  // would answer with silence to the end (SafeDevice's own tests cover that wait).
  safety.onset_force = std::numeric_limits<double>::infinity();
  Harness run(
      keyframe_target({{0.0, at({0.0, 0.0, radius + 0.02})}, {0.3, at({0.0, 0.0, pressed})}}),
      b.scene, coupling_options(radius), b.penetration(), safety);
  constexpr int faulty = 5;
  run.run(1000);
  const Eigen::Vector3d steady = run.trace().back().record.rendered.force;
  ASSERT_GT(steady.z(), 2.0) << "in contact, pressing";
  for (const int start : {1000, 1600}) {
    if (start == 1000) {
      run.device().inject_invalid_pose(faulty);
    } else {
      run.run(start - static_cast<int>(run.trace().size()));
      run.device().inject_disconnect(faulty);
    }
    // The very cycle the fault starts in renders zero and leaves the simulation object alone,
    // and so do the following faulty ones. The held ball still rests on the floor: the World
    // queries it there (another hand's body could be touching it), and the record holds that
    // fresh contact, equal to a separate query at the held pose.
    const Pose held = run.trace().back().record.simulation;
    contact::ContactWorkspace reference(b.ball, analytic_options(HapticObject::pointshell));
    contact::ContactFrames frames;
    frames.pointshell = held_body_pose(held, Eigen::Vector3d::Zero());
    frames.grasp_point = held.position;
    ASSERT_TRUE(contact::query_contact(b.ball, b.floor, frames, reference));
    const Eigen::Vector3d resting = reference.result().force;
    ASSERT_GT(resting.z(), 0.0) << "the ball rests on the floor";
    for (int i = 0; i < faulty; ++i) {
      const CycleRecord& r = run.step().record;
      EXPECT_FALSE(r.device_valid) << start << " + " << i;
      EXPECT_TRUE(r.contact_valid) << start << " + " << i;
      // With friction the World's anchors pull too, which a fresh workspace has none of:
      // within the friction cone, μ_s times the normal force.
      EXPECT_LE((r.contact.force - resting).norm(),
                (frictionless() ? 1e-9 : GetParam().friction.static_coefficient) * resting.norm())
          << "this cycle's contact at the held pose, " << start << " + " << i;
      EXPECT_EQ(r.rendered.force, Eigen::Vector3d::Zero()) << start << " + " << i;
      EXPECT_EQ(r.rendered.torque, Eigen::Vector3d::Zero()) << start << " + " << i;
      EXPECT_EQ(r.simulation.position, held.position) << start << " + " << i;
      EXPECT_EQ(r.simulation.orientation.coeffs(), held.orientation.coeffs());
      EXPECT_EQ(run.device().applied_wrench().force, Eigen::Vector3d::Zero());
    }
    // Recovery through the ramp: the k-th write after the fault is at most k/N of the device's
    // limit, then the loop settles back to the same equilibrium as before.
    for (int k = 1; k <= safety.ramp_cycles; ++k) {
      const CycleRecord& r = run.step().record;
      EXPECT_TRUE(r.device_valid && r.coupling_valid);
      EXPECT_LE(r.rendered.force.norm(),
                k * run.device().capabilities().max_force / safety.ramp_cycles * (1 + round_off));
    }
  }
  run.run(2600 - static_cast<int>(run.trace().size()));
  const std::vector<Sample>& trace = run.trace();
  ASSERT_EQ(first_non_finite(trace), trace.size());
  EXPECT_LT((trace.back().record.rendered.force - steady).norm(), 0.01 * steady.norm());
  // The device sank while nothing was rendered, but saturation kept the ball out of the floor.
  EXPECT_LE(largest(trace, 0, trace.size(), [](const Sample& s) { return s.penetration; }), voxel);
  expect_settled(trace, 300);
  const CycleRecord& last = trace.back().record;
  EXPECT_LE(quasi_static_stiffness(run.coupling(), run.world(), last.manipulandum,
                                   -Eigen::Vector3d::UnitZ(), 1e-4),
            coupling_stiffness * (1.0 + 1e-6));
}

// Late cycles (issue 19 item 6): a ball pressed onto a floor with 3 N and slid sideways at
// 5 cm/s; three times the loop stalls, for 5, 20 and 100 ms, the device holding its last output
// meanwhile (SimulatedOperator::inject_stall()) and the safety layer seeing the late cycle. The
// writes after it move from the held force to the fresh one over the 20-cycle ramp instead of
// dropping to zero, so no cycle's rendered force differs from the last by more than 5 % of the
// press, and the stall gives the hand no energy: the passivity observer (CycleMetrics) never
// falls below its value before the stall.
TEST_P(HapticHardCases, AStalledLoopRendersNoSpikeAndGivesNoEnergy) {
  const BallOnFloor b(analytic_options(HapticObject::pointshell));
  const double radius = BallOnFloor::radius, pressed = b.pressed;
  SafetyOptions safety;
  safety.ramp_cycles = 20;
  Harness run(keyframe_target({{0.0, at({0.0, 0.0, radius + 0.02})},
                               {0.3, at({0.0, 0.0, pressed})},
                               {0.5, at({0.0, 0.0, pressed})},
                               {3.5, at({0.15, 0.0, pressed})}}),
              b.scene, coupling_options(radius), b.penetration(), safety);
  run.run(1000);
  const double press = run.trace().back().record.rendered.force.norm();
  ASSERT_GT(press, 2.0) << "pressed";
  for (const int stall : {5, 20, 100}) {
    const double energy_before = run.trace().back().record.observed_energy;
    run.stall(stall);
    double largest_jump = 0.0, lowest_energy = energy_before;
    for (int i = 0; i < 300; ++i) {
      const Eigen::Vector3d before = run.trace().back().record.rendered.force;
      const CycleRecord& r = run.step().record;
      ASSERT_TRUE(r.device_valid && r.contact_valid && r.coupling_valid);
      largest_jump = std::max(largest_jump, (r.rendered.force - before).norm());
      lowest_energy = std::min(lowest_energy, r.observed_energy);
    }
    EXPECT_LE(largest_jump, 0.05 * press) << stall << " ms";
    EXPECT_GE(lowest_energy, energy_before - 1e-9) << stall << " ms";
    std::printf(
        "stall %3d ms: largest jump %.3f N (press %.2f N); observer %.5f J, lowest after "
        "%.5f J\n",
        stall, largest_jump, press, energy_before, lowest_energy);
  }
  const std::vector<Sample>& trace = run.trace();
  ASSERT_EQ(first_non_finite(trace), trace.size());
  EXPECT_LE(largest(trace, 0, trace.size(), [](const Sample& s) { return s.penetration; }), voxel);
}

// Start-up inside an object (issue 19 item 6): the held ball starts 1 cm deep in the floor, the
// hand holds it there for 0.3 s, lifts it 2 cm over a second, and then presses it onto the floor
// with 3 N. The coupling starts with its simulation object at the manipulandum, so its first
// cycles ask for almost no force while the contact pushes the ball out; the force the hand then
// feels is the saturated coupling's 3 N, which would arrive as a kick. The safety layer's wait
// for a small force (1 N, CHAI3D's waitForSmallForce) also waits for the contact force on the
// held ball (World passes it as the pending force): nothing is rendered while the hand is inside,
// then at most the 1 N threshold, and the later press renders as usual.
TEST_P(HapticHardCases, StartingInsideAnObjectRendersNothingUntilTheHandIsOut) {
  const BallOnFloor b(analytic_options(HapticObject::pointshell));
  const double radius = BallOnFloor::radius, pressed = b.pressed;
  SafetyOptions safety;
  safety.ramp_cycles = 20;
  Harness run(keyframe_target({{0.0, at({0.0, 0.0, radius - 0.01})},
                               {0.3, at({0.0, 0.0, radius - 0.01})},
                               {1.3, at({0.0, 0.0, radius + 0.01})},
                               {1.6, at({0.0, 0.0, radius + 0.01})},
                               {2.2, at({0.0, 0.0, pressed})}}),
              b.scene, coupling_options(radius), b.penetration(), safety);
  run.run(1600);
  std::vector<Sample> trace = run.trace();
  ASSERT_EQ(first_non_finite(trace), trace.size());
  EXPECT_EQ(trace.front().record.rendered.force, Eigen::Vector3d::Zero());
  EXPECT_GT(trace.front().record.contact.force.norm(), safety.onset_force)
      << "the ball starts pressed into the floor";
  const double strongest = largest(trace, 0, trace.size(),
                                   [](const Sample& s) { return s.record.rendered.force.norm(); });
  EXPECT_LE(strongest, safety.onset_force * (1.0 + round_off));
  // No kick: a force stepping up to F on the hand's spring k_h gives it at most F²/2k_h of
  // kinetic energy, 1.7 mJ at the threshold (the saturated coupling's 3 N would allow 15 mJ).
  const double liveliest =
      largest(trace, 0, trace.size(), [](const Sample& s) { return s.device_energy; });
  EXPECT_LE(liveliest, safety.onset_force * safety.onset_force / (2.0 * HandModel{}.stiffness));
  std::printf("start inside: strongest rendered force %.3f N, largest device energy %.2e J\n",
              strongest, liveliest);
  // Then an ordinary press renders the coupling's force.
  run.run(1400);
  EXPECT_GT(run.trace().back().record.rendered.force.z(), 2.0);
  EXPECT_EQ(run.safe().last_write_events() & safety_waiting_for_small_force, 0u);
}

// Start-up turned (issue 19 item 6, 6-DOF): the workspace mapping turns the device's frame by a
// quarter turn, so the manipulandum starts a quarter turn away from the held ball, which the
// coupling would answer with its whole torque at once. The wait also covers the torque
// (onset_torque, 0.05 N·m): nothing is rendered while the coupling turns the ball into line,
// then no more than the threshold.
TEST_P(HapticHardCases, StartingTurnedAwayFromTheHeldObjectGivesNoTorqueKick) {
  const BallOnFloor b(analytic_options(HapticObject::pointshell));
  const double radius = BallOnFloor::radius;
  SafetyOptions safety;
  safety.ramp_cycles = 20;
  Harness run(keyframe_target({{0.0, at({0.0, 0.0, radius + 0.05})}}), b.scene,
              coupling_options(radius), b.penetration(), safety);
  // Turned about the device's starting point, which stays where it is.
  WorkspaceMapping turned_frame;
  turned_frame.offset.orientation = turned(std::numbers::pi / 2, Eigen::Vector3d::UnitX());
  const Eigen::Vector3d start(0.0, 0.0, radius + 0.05);
  turned_frame.offset.position = start - turned_frame.offset.orientation * start;
  run.safe().set_mapping(turned_frame);
  run.run(1000);
  const std::vector<Sample>& trace = run.trace();
  ASSERT_EQ(first_non_finite(trace), trace.size());
  EXPECT_EQ(trace.front().record.rendered.torque, Eigen::Vector3d::Zero());
  const double strongest = largest(trace, 0, trace.size(),
                                   [](const Sample& s) { return s.record.rendered.torque.norm(); });
  EXPECT_LE(strongest, safety.onset_torque * (1.0 + round_off));
  // The ball has turned into line with the hand, and output runs.
  const Eigen::Quaterniond& simulation = trace.back().record.simulation.orientation;
  EXPECT_LT(simulation.angularDistance(trace.back().record.manipulandum.orientation), 1e-3);
  EXPECT_EQ(run.safe().last_write_events() & safety_waiting_for_small_force, 0u);
  std::printf("start turned: strongest rendered torque %.4f N m\n", strongest);
}

// ---------------------------------------------------------------------------------------------
// 11. Friction over a closed path (issue 20).

// The ball pressed onto the floor with friction μ_s = 0.5, μ_k = 0.4, slid 5 cm out, 2 cm
// aside, back, and lifted to where it started. Over the closed path the hand gave the simulation
// energy (the passivity observer ends above zero): at a steady press friction dissipates (not
// when a stuck point's depth changes: docs/CONTACT.md). Its points stuck and slid, and the loop
// stayed as safe as every hard case.
TEST(HapticHardCasesWithFriction, ABallSlidAlongAClosedPathTakesTheHandsEnergy) {
  const BallOnFloor b(
      contact_options(HapticObject::pointshell, on_analytic_field(rubbings().back().friction)));
  const double radius = BallOnFloor::radius;
  Harness run(keyframe_target({{0.0, at({0.0, 0.0, radius + 0.02})},
                               {0.3, at({0.0, 0.0, b.pressed})},
                               {0.5, at({0.0, 0.0, b.pressed})},
                               {1.5, at({0.05, 0.0, b.pressed})},
                               {1.6, at({0.05, 0.02, b.pressed})},
                               {2.6, at({0.0, 0.0, b.pressed})},
                               {2.9, at({0.0, 0.0, radius + 0.02})}}),
              b.scene, coupling_options(radius), b.penetration());
  run.run(4500);
  const std::vector<Sample>& trace = run.trace();
  ASSERT_EQ(first_non_finite(trace), trace.size());
  std::int64_t sliding = 0, stuck = 0;
  for (std::size_t i = 1; i < trace.size(); ++i) {
    const CycleRecord& r = trace[i].record;
    ASSERT_TRUE(r.device_valid && r.contact_valid && r.coupling_valid) << "cycle " << i;
    ASSERT_LE((r.simulation.position - trace[i - 1].record.simulation.position).norm(),
              max_step() * (1.0 + round_off))
        << "cycle " << i;
    sliding += r.contact.statistics.points_sliding;
    stuck += r.contact.statistics.points_in_contact - r.contact.statistics.points_sliding;
  }
  EXPECT_GT(sliding, 0);
  EXPECT_GT(stuck, 0);
  expect_safe_ending(run, -Eigen::Vector3d::UnitZ());
  const double energy = trace.back().record.observed_energy;
  EXPECT_GT(energy, 0.0) << "friction dissipated the hand's work";
  std::printf("ball's closed path with friction: the hand did %.4g J of work on it\n", energy);
}

}  // namespace
}  // namespace khz::haptic::hard_cases
