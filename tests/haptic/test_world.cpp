// World: the multi-body runtime. One hand and one pair is the thesis's single-object cycle
// (Figure 4.2, written out here from the query, coupling and safety-layer calls) and renders a
// floor without penetrating it or gaining energy; two hands holding two bodies feel one contact
// as action and reaction; a cycle allocates nothing; bad set-ups are refused naming the body or
// hand.
#include "hard_case_fixtures.hpp"

#include <khz/contact/field/implicit_shapes.hpp>
#include <khz/contact/query/contact_query.hpp>
#include <khz/haptic/device/simulated_operator.hpp>
#include <khz/haptic/world/world.hpp>
#include <khz/test/allocation_probe.hpp>
#include <khz/test/fixtures.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <memory>

namespace khz::haptic {
namespace {

using hard_cases::at;
using test::throws_with_message;

constexpr double ball_radius = 0.05;  // m

/// A 5 cm ball sampled by 5,440 near-uniform points in 4 levels, inward normals.
const contact::PointTree& ball() {
  static const contact::PointTree tree =
      hard_cases::nested_tree(hard_cases::sphere_pointshell(ball_radius, 85 * 64), 85);
  return tree;
}

/// A simulated hand whose anchor moves from `from` to `to` in 0.5 s and holds, behind its
/// safety layer, opened.
struct ScriptedHand {
  ScriptedHand(const Eigen::Vector3d& from, const Eigen::Vector3d& to)
      : device(keyframe_target({{0.0, at(from)}, {0.5, at(to)}}), SimulatedOperatorOptions{}),
        safe(device) {
    safe.open();
  }
  SimulatedOperator device;
  SafeDevice safe;
};

CouplingOptions coupling_options() {
  CouplingOptions options;
  options.stiffness = 500.0;
  options.max_rendered_force = SimulatedOperatorOptions{}.capabilities.max_force;
  return options;
}

contact::ContactOptions contact_options() {
  contact::ContactOptions options;
  options.haptic_object = contact::HapticObject::pointshell;
  options.stiffness = 2000.0;
  return options;
}

const contact::ImplicitShape& floor_shape() {
  static const contact::ImplicitShape floor = contact::HalfSpace(Eigen::Vector3d::UnitZ(), 0.0);
  return floor;
}

/// Bodies 0: the ball (pointshell), held; 1: the floor (field), fixed, at the ball's start.
std::vector<Body> ball_and_floor(const Eigen::Vector3d& ball_start) {
  Body held;
  held.name = "ball";
  held.pose.translation() = ball_start;
  held.pointshell = &ball();
  Body floor;
  floor.name = "floor";
  floor.field = &floor_shape();
  return {held, floor};
}

/// The single-object cycle of thesis Figure 4.2 written out from library calls, one pointshell
/// held against one fixed field: read the device, query at the simulation pose, step the
/// coupling, write the rendered wrench (zero if anything failed).
class SingleObjectCycle {
 public:
  SingleObjectCycle(SafeDevice& device, const Pose& start)
      : m_device(device),
        m_coupling(coupling_options(), start),
        m_workspace(ball(), contact_options()) {}

  CycleRecord run(double now) {
    m_device.begin_cycle(now + 1e-3);
    CycleRecord r;
    r.time = now;
    DeviceState state;
    r.device_valid = m_device.read(state);
    r.manipulandum = state.pose;
    Wrench rendered;
    if (r.device_valid) {
      contact::ContactFrames frames;
      frames.pointshell = held_body_pose(m_coupling.simulation_pose(), Eigen::Vector3d::Zero());
      frames.grasp_point = m_coupling.simulation_pose().position;
      r.contact_valid = contact::query_contact(ball(), floor_shape(), frames, m_workspace);
      if (r.contact_valid) {
        r.contact = m_workspace.result();
        const CouplingStep step = m_coupling.step(state.pose, r.contact);
        r.coupling_valid = step.valid;
        if (step.valid) rendered = step.rendered;
      }
    }
    r.simulation = m_coupling.simulation_pose();
    m_device.write(rendered);
    r.rendered = m_device.last_output();
    m_device.end_cycle(now + 1e-4);
    return r;
  }

 private:
  SafeDevice& m_device;
  VirtualCoupling m_coupling;
  contact::ContactWorkspace m_workspace;
};

/// Hand 0 holding body 0 through `hand`'s safety layer, with coupling_options().
Hand holding_body_0(ScriptedHand& hand) {
  return hard_cases::holding_body_0(hand.safe, coupling_options());
}

// The one-hand, one-pair world is the single-object cycle: pressing a ball onto a floor, every
// cycle's record agrees with the cycle written out by hand to round-off (the two compile the
// query in different places).
TEST(World, OneHandAndOnePairIsTheSingleObjectCycle) {
  const Eigen::Vector3d start(0.0, 0.0, ball_radius + 0.05), end(0.0, 0.0, ball_radius - 0.03);
  ScriptedHand reference_hand(start, end), world_hand(start, end);
  SingleObjectCycle reference(reference_hand.safe, at(start));
  World world(ball_and_floor(start), {holding_body_0(world_hand)}, contact_options());
  ASSERT_EQ(world.pairs().size(), 1u);
  EXPECT_EQ(world.pairs()[0].pointshell, 0);
  EXPECT_EQ(world.pairs()[0].field, 1);

  double largest_force = 0.0, largest_difference = 0.0;
  for (int i = 0; i < 1500; ++i) {
    const double now = i * 1e-3;
    const CycleRecord expected = reference.run(now);
    const std::span<const CycleRecord> records =
        world.cycle(now, now + 1e-3, [&] { return now + 1e-4; });
    ASSERT_EQ(records.size(), 1u);
    const CycleRecord& r = records[0];
    ASSERT_TRUE(r.device_valid && r.contact_valid && r.coupling_valid && r.integrators_ok);
    ASSERT_TRUE(expected.device_valid && expected.contact_valid && expected.coupling_valid);
    EXPECT_EQ(r.contact.statistics.points_in_contact, expected.contact.statistics.points_in_contact)
        << "cycle " << i;
    largest_force = std::max(largest_force, expected.contact.force.norm());
    largest_difference =
        std::max({largest_difference, (r.contact.force - expected.contact.force).norm(),
                  (r.rendered.force - expected.rendered.force).norm(),
                  500.0 * (r.simulation.position - expected.simulation.position).norm()});
  }
  EXPECT_GT(largest_force, 1.0) << "the ball reached the floor";
  EXPECT_LE(largest_difference, 1e-9 * largest_force);
  std::printf("largest difference from the single-object cycle: %.3g N (peak force %.3g N)\n",
              largest_difference, largest_force);
}

TEST(World, AHandPressingABallOnAFloorFeelsItWithoutPenetratingOrGainingEnergy) {
  // The hand's anchor moves from 5 cm above contact to 3 cm below the floor in 0.5 s and holds:
  // the device should stop at the floor, render up to its 8.5 N, and settle.
  const Eigen::Vector3d start(0.0, 0.0, ball_radius + 0.05), end(0.0, 0.0, ball_radius - 0.03);
  ScriptedHand hand(start, end);
  World world(ball_and_floor(start), {holding_body_0(hand)}, contact_options());
  double deepest = 0.0, strongest = 0.0, energy_late = 0.0, energy_peak_late = 0.0;
  for (int i = 0; i < 3000; ++i) {
    const double now = i * 1e-3;
    const CycleRecord& r = world.cycle(now, now + 1e-3, [&] { return now + 1e-4; })[0];
    ASSERT_TRUE(r.device_valid && r.contact_valid && r.coupling_valid) << "cycle " << i;
    ASSERT_TRUE(r.simulation.position.allFinite() && r.rendered.force.allFinite());
    deepest = std::max(deepest, ball_radius - r.simulation.position.z());
    strongest = std::max(strongest, r.rendered.force.norm());
    if (i >= 2000) {
      const double e = hand.device.kinetic_energy();
      energy_late += e / 1000.0;
      energy_peak_late = std::max(energy_peak_late, e);
    }
  }
  const CycleRecord& last = world.records()[0];
  // The ball rests on the floor: penetration well below a millimetre (the contact is ~40× stiffer
  // than the coupling), while the device sinks below it (virtual coupling, §3.1.1) until the
  // rendered spring k_VC (x_s − x_m) balances the hand's spring k_h (x_m − anchor).
  EXPECT_LT(deepest, 1e-3);
  EXPECT_GT(deepest, 0.0);
  EXPECT_GT(last.contact.force.z(), 1.0) << "the floor holds the ball up";
  const double sunk = last.simulation.position.z() - hand.device.pose().position.z();
  EXPECT_GT(sunk, 0.005) << "the manipulandum is below the ball it holds";
  EXPECT_NEAR(last.rendered.force.z(), coupling_options().stiffness * sunk, 1e-6);
  const SimulatedOperatorOptions operator_options;
  const double hand_force =
      operator_options.hand.stiffness *
      (hand.device.pose().position.z() - hand.device.target_pose().position.z());
  EXPECT_NEAR(last.rendered.force.z(), hand_force, 0.02 * hand_force);
  EXPECT_LE(strongest, operator_options.capabilities.max_force * (1.0 + 1e-12));
  // At rest: the device does not oscillate against the rendered wall.
  EXPECT_LT(energy_peak_late, 1e-6) << "mean " << energy_late;
}

// World::metrics() is the hand's records in figures: the largest force jump and the peak as the
// records give them, the deepest point as the geometry gives it, and the passivity observer as
// the work of each rendered force over the device's next motion (identity mapping).
TEST(World, MetricsAreTheHandsRecordsInFigures) {
  const Eigen::Vector3d start(0.0, 0.0, ball_radius + 0.02), end(0.0, 0.0, ball_radius - 0.03);
  ScriptedHand hand(start, end);
  World world(ball_and_floor(start), {holding_body_0(hand)}, contact_options());
  double largest_jump = 0.0, peak = 0.0, lowest = 0.0, energy = 0.0, deepest = 0.0;
  CycleRecord previous;
  for (int i = 0; i < 1500; ++i) {
    const double now = i * 1e-3;
    const CycleRecord r = world.cycle(now, now + 1e-3, [&] { return now + 1e-4; })[0];
    if (i > 0) {
      largest_jump = std::max(largest_jump, (r.contact.force - previous.contact.force).norm());
      energy -=
          previous.rendered.force.dot(r.manipulandum.position - previous.manipulandum.position);
      lowest = std::min(lowest, energy);
    }
    // The observer also counts the rendered torque's work over the device's (tiny) turns.
    EXPECT_NEAR(r.observed_energy, energy, 1e-9 * std::abs(energy) + 1e-12) << "cycle " << i;
    peak = std::max(peak, r.contact.force.norm());
    // The deepest point of the ball under the floor, from its centre (the pointshell's bottom
    // point is within a point spacing of the sphere's, 1.4e-5 m deeper at most).
    if (r.contact.statistics.points_in_contact > 0) {
      deepest = std::max(deepest, ball_radius - world.bodies()[0].pose.translation().z());
    }
    EXPECT_EQ(r.penetration_voxels, 0.0) << "an analytic floor has no voxels";
    previous = r;
  }
  const CycleMetricsSummary s = world.metrics(0);
  EXPECT_EQ(s.cycles, 1500);
  EXPECT_GT(peak, 1.0);
  EXPECT_EQ(s.peak_contact_force, peak);
  EXPECT_EQ(s.contact_force_jump.max, largest_jump);
  EXPECT_NEAR(s.energy, energy, 1e-9 * std::abs(energy));
  EXPECT_NEAR(s.lowest_energy, lowest, 1e-12);
  EXPECT_GT(s.energy, 0.0) << "the hand pushed the ball into the floor";
  EXPECT_LE(s.deepest_penetration, deepest);
  EXPECT_GE(s.deepest_penetration, deepest - 2e-5);
  EXPECT_GT(s.residual_force.count, 500);
  // Still from when the device has settled on the floor: the ball rests to well under 1 µm.
  EXPECT_GT(s.still_translation.count, 100);
  EXPECT_LT(s.still_translation.max, 1e-6);
  std::printf(
      "force jump p50 %.3g p99 %.3g max %.3g N (peak %.3g N); residual p99 %.3g N; "
      "still step max %.3g m; energy %.3g J, lowest %.3g J\n",
      s.contact_force_jump.p50, s.contact_force_jump.p99, s.contact_force_jump.max,
      s.peak_contact_force, s.residual_force.p99, s.still_translation.max, s.energy,
      s.lowest_energy);
  world.reset_metrics();
  EXPECT_EQ(world.metrics(0).cycles, 0);
}

// Two hands: one holds the ball, the other a box it presses on. Each feels the one contact,
// as action and reaction: opposite forces, and torques that differ by the lever between the two
// grasp points; a fixed floor under the box is touched by neither (the box has no pointshell).
TEST(World, TwoHandsHoldingTwoBodiesFeelActionAndReaction) {
  const contact::ImplicitShape box =
      contact::Box(Eigen::Vector3d::Zero(), Eigen::Vector3d(0.1, 0.1, 0.02));
  // The ball comes down on the box's top face, off its centre so there is a torque.
  ScriptedHand ball_hand({0.03, 0.0, 0.02 + ball_radius + 0.03}, {0.03, 0.0, 0.02 + 0.03});
  ScriptedHand box_hand({0.0, 0.0, 0.0}, {0.0, 0.0, 0.0});
  std::vector<Body> bodies = ball_and_floor({0.03, 0.0, 0.02 + ball_radius + 0.03});
  bodies[1].pose.translation() = Eigen::Vector3d(0.0, 0.0, -1.0);  // far below: never touched
  Body held_box;
  held_box.name = "box";
  held_box.field = &box;
  bodies.push_back(held_box);
  Hand ball_grip, box_grip;
  ball_grip.body = 0;
  ball_grip.device = &ball_hand.safe;
  ball_grip.coupling = coupling_options();
  box_grip.body = 2;
  box_grip.device = &box_hand.safe;
  box_grip.coupling = coupling_options();
  World world(std::move(bodies), {ball_grip, box_grip}, contact_options());
  // Ball–floor for the ball's hand; ball–box once for each hand.
  ASSERT_EQ(world.pairs().size(), 3u);

  int both_in_contact = 0;
  for (int i = 0; i < 1200; ++i) {
    const double now = i * 1e-3;
    // The grasp points the cycle queries at: each coupling's simulation pose before it steps.
    const Eigen::Vector3d ball_grasp = world.coupling(0).simulation_pose().position;
    const Eigen::Vector3d box_grasp = world.coupling(1).simulation_pose().position;
    const std::span<const CycleRecord> r = world.cycle(now, now + 1e-3, [&] { return now; });
    ASSERT_EQ(r.size(), 2u);
    for (const CycleRecord& record : r) {
      ASSERT_TRUE(record.device_valid && record.contact_valid && record.coupling_valid);
      ASSERT_TRUE(record.contact.force.allFinite() && record.rendered.force.allFinite());
    }
    if (r[0].contact.statistics.points_in_contact == 0) continue;
    ++both_in_contact;
    EXPECT_EQ(r[1].contact.statistics.points_in_contact, r[0].contact.statistics.points_in_contact);
    const Eigen::Vector3d& f = r[0].contact.force;
    EXPECT_LE((r[1].contact.force + f).norm(), 1e-12 * f.norm()) << "cycle " << i;
    // T_box = −T_ball − (g_ball − g_box) × F_ball, each about its own grasp point.
    const Eigen::Vector3d reaction = -r[0].contact.torque - (ball_grasp - box_grasp).cross(f);
    EXPECT_LE((r[1].contact.torque - reaction).norm(), 1e-12 * f.norm() + 1e-12 * reaction.norm())
        << "cycle " << i;
  }
  EXPECT_GT(both_in_contact, 500);
  const CycleRecord& ball_record = world.records()[0];
  const CycleRecord& box_record = world.records()[1];
  EXPECT_GT(ball_record.contact.force.z(), 1.0) << "the box holds the ball up";
  EXPECT_LT(box_record.contact.force.z(), -1.0) << "the ball pushes the box down";
  EXPECT_GT(ball_record.rendered.force.z(), 0.5) << "the ball's hand feels it";
  EXPECT_LT(box_record.rendered.force.z(), -0.5) << "the box's hand feels it";
  EXPECT_LE(ball_record.rendered.force.norm(), coupling_options().max_rendered_force);
  EXPECT_EQ(world.pair_result(0).statistics.points_in_contact, 0) << "the floor is far below";
}

TEST(World, ACycleAllocatesNothing) {
  const Eigen::Vector3d start(0.0, 0.0, ball_radius + 0.01), end(0.0, 0.0, ball_radius - 0.03);
  ScriptedHand scripted(start, end);
  World world(ball_and_floor(start), {holding_body_0(scripted)}, contact_options());
  for (int i = 0; i < 300; ++i) world.cycle(i * 1e-3, (i + 1) * 1e-3, [&] { return i * 1e-3; });
  ASSERT_GT(world.records()[0].contact.statistics.points_in_contact, 0);
  test::allocation_count = 0;
  for (int i = 300; i < 400; ++i) world.cycle(i * 1e-3, (i + 1) * 1e-3, [&] { return i * 1e-3; });
  EXPECT_EQ(test::allocation_count, 0u);
  EXPECT_GT(world.records()[0].contact.statistics.points_in_contact, 0);
}

// probe() queries at the grasp frames it is given and nothing else: against a separate query of
// the same pair at the same frames (the torque about the probed grasp point), with no device
// read, no coupling or body moved for good, no allocation; a wrong count of grasps is refused.
TEST(World, ProbeQueriesAtTheGivenGraspsAndStepsNothing) {
  const Eigen::Vector3d start(0.0, 0.0, ball_radius + 0.01);
  ScriptedHand scripted(start, start);
  World world(ball_and_floor(start), {holding_body_0(scripted)}, contact_options());
  world.cycle(0.0, 1e-3, [] { return 0.0; });
  const Pose coupled = world.coupling(0).simulation_pose();

  Pose pressed = at(Eigen::Vector3d(0.01, 0.0, ball_radius - 0.004));
  pressed.orientation = Eigen::Quaterniond(Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitX()));
  const Pose grasps[] = {pressed};
  test::allocation_count = 0;
  ASSERT_TRUE(world.probe(grasps));
  EXPECT_EQ(test::allocation_count, 0u);

  contact::ContactWorkspace workspace(ball(), contact_options());
  contact::ContactFrames frames;
  frames.pointshell.linear() = pressed.orientation.toRotationMatrix();
  frames.pointshell.translation() = pressed.position;  // the grasp point is the ball's centre
  frames.grasp_point = pressed.position;
  ASSERT_TRUE(contact::query_contact(ball(), floor_shape(), frames, workspace));
  const contact::ContactResult& expected = workspace.result();
  ASSERT_GT(expected.statistics.points_in_contact, 0);
  const contact::ContactWrench& probed = world.wrench(0);
  EXPECT_LE((probed.force - expected.force).norm(), 1e-12 * expected.force.norm());
  EXPECT_LE((probed.torque - expected.torque).norm(), 1e-12 * expected.force.norm());
  EXPECT_EQ(probed.statistics.points_in_contact, expected.statistics.points_in_contact);
  EXPECT_TRUE(world.bodies()[0].pose.translation().isApprox(pressed.position));

  EXPECT_EQ(world.coupling(0).simulation_pose().position, coupled.position);
  const Pose two[] = {pressed, pressed};
  EXPECT_FALSE(world.probe(two));
}

TEST(World, APairFilterLeavesPairsOut) {
  ScriptedHand scripted({0, 0, 1}, {0, 0, 1});
  Hand hand;
  hand.device = &scripted.safe;
  std::vector<Body> bodies = ball_and_floor({0, 0, 1});
  bodies.push_back(bodies[1]);  // a second floor
  bodies[2].name = "second floor";
  World world(bodies, {hand}, contact_options(), [](int a, int b) { return !(a == 0 && b == 2); });
  ASSERT_EQ(world.pairs().size(), 1u);
  EXPECT_EQ(world.pairs()[0].field, 1);
  EXPECT_TRUE(throws_with_message<Error>(
      [&] { World none(bodies, {hand}, contact_options(), [](int, int) { return false; }); },
      "no moving body can touch another body"));
}

// Per-pair friction (World::set_pair_friction, contact::FrictionOptions): a hand presses the
// ball on the floor and slides it. Frictionless, the ball follows the hand and the hand feels no
// drag; with μ_k = 0.4 it feels the kinetic drag, μ_k times the normal force, against its motion.
TEST(World, PairFrictionDragsAHandSlidingABallAlongTheFloor) {
  const auto drag_over_normal = [](const contact::FrictionOptions* friction) {
    const Eigen::Vector3d start(0.0, 0.0, ball_radius + 0.02);
    const Eigen::Vector3d pressed(0.0, 0.0, ball_radius - 0.01);
    SimulatedOperator device(keyframe_target({{0.0, at(start)},
                                              {0.3, at(pressed)},
                                              {0.6, at(pressed)},
                                              {1.6, at(pressed + Eigen::Vector3d(0.05, 0, 0))}}),
                             SimulatedOperatorOptions{});
    SafeDevice safe(device);
    safe.open();
    Hand hand;
    hand.body = 0;
    hand.device = &safe;
    hand.coupling = coupling_options();
    std::vector<Body> bodies = ball_and_floor(start);
    World world(std::move(bodies), {hand}, contact_options());
    if (friction != nullptr) world.set_pair_friction(1, 0, *friction);
    double drag = 0.0, normal = 0.0;
    std::int64_t sliding = 0;
    for (int i = 0; i < 1600; ++i) {
      const double now = i * 1e-3;
      const CycleRecord& r = world.cycle(now, now + 1e-3, [&] { return now + 1e-4; })[0];
      EXPECT_TRUE(r.device_valid && r.contact_valid && r.coupling_valid) << "cycle " << i;
      if (i >= 900) {  // sliding steadily
        drag += r.rendered.force.x();
        normal += r.rendered.force.z();
        sliding += r.contact.statistics.points_sliding;
      }
    }
    EXPECT_EQ(sliding > 0, friction != nullptr);
    // The points friction_state() calls sliding are the ones the last query counted.
    std::int64_t sliding_now = 0;
    for (Eigen::Index s = 0; s < ball().num_points(); ++s) {
      sliding_now += world.friction_state(0, s) == contact::FrictionState::sliding ? 1 : 0;
    }
    EXPECT_EQ(sliding_now, world.pair_result(0).statistics.points_sliding);
    return drag / normal;
  };
  const contact::FrictionOptions friction{0.5, 0.4, 1e-4};
  EXPECT_LT(std::abs(drag_over_normal(nullptr)), 0.02);
  const double dragged = drag_over_normal(&friction);
  EXPECT_LT(dragged, -0.35) << "the kinetic drag, against the motion (+x)";
  EXPECT_GT(dragged, -0.45);
}

TEST(World, RefusesPairFrictionForBodiesThatDoNotTouch) {
  ScriptedHand scripted({0, 0, 1}, {0, 0, 1});
  std::vector<Body> bodies = ball_and_floor({0, 0, 1});
  bodies.push_back(bodies[1]);
  bodies[2].name = "wall";
  World world(std::move(bodies), {holding_body_0(scripted)}, contact_options());
  const contact::FrictionOptions friction{0.5, 0.4, 1e-4};
  world.set_pair_friction(0, 2, friction);
  EXPECT_EQ(world.pair_friction(1).static_coefficient, 0.5);
  EXPECT_EQ(world.pair_friction(0).static_coefficient, 0.0) << "ball–floor keeps the scene's";
  EXPECT_TRUE(throws_with_message<Error>([&] { world.set_pair_friction(1, 2, friction); },
                                         "body 'floor' and body 'wall' never touch"));
  EXPECT_TRUE(throws_with_message<Error>([&] { world.set_pair_friction(0, 0, friction); },
                                         "body 'ball' given twice"));
  EXPECT_TRUE(throws_with_message<Error>([&] { world.set_pair_friction(0, 3, friction); },
                                         "bodies 0 and 3 (there are 3)"));
  EXPECT_TRUE(throws_with_message<Error>(
      [&] {
        world.set_pair_friction(0, 1, {0.2, 0.3, 1e-4});
      },
      "friction.kinetic_coefficient must be finite, ≥ 0 and at most"));
  // The floor is analytic: no voxel to choose the default stick distance from.
  EXPECT_TRUE(throws_with_message<Error>(
      [&] {
        world.set_pair_friction(0, 1, {0.5, 0.4, 0.0});
      },
      "World: friction between body 'ball' and body 'floor' needs a stick_distance"));
  contact::ContactOptions automatic = contact_options();
  automatic.friction = {0.5, 0.4, 0.0};
  EXPECT_TRUE(throws_with_message<Error>([&] { world.set_contact_options(automatic); },
                                         "the field of body 'floor' is an analytic shape"));
  // set_contact_options() keeps a pair's own friction.
  world.set_contact_options(contact_options());
  EXPECT_EQ(world.pair_friction(1).static_coefficient, 0.5);
}

TEST(World, RefusesBadSetUpsNamingTheBodyOrHand) {
  ScriptedHand scripted({0, 0, 1}, {0, 0, 1});
  const std::vector<Body> bodies = ball_and_floor({0, 0, 1});
  Hand hand;
  hand.device = &scripted.safe;
  const auto refuses = [&](std::vector<Body> b, std::vector<Hand> h, const char* message) {
    return throws_with_message<Error>(
        [&] { World world(std::move(b), std::move(h), contact_options()); }, message);
  };
  Hand outside = hand;
  outside.body = 2;
  EXPECT_TRUE(refuses(bodies, {outside}, "hand 0 holds body 2, but there are 2 bodies"));
  EXPECT_TRUE(refuses(bodies, {hand, hand}, "hand 1 holds body 'ball', which hand 0 holds"));
  Hand deviceless = hand;
  deviceless.device = nullptr;
  EXPECT_TRUE(refuses(bodies, {deviceless}, "hand 0 has no device"));
  std::vector<Body> bare = bodies;
  bare[0].pointshell = {};
  EXPECT_TRUE(refuses(bare, {hand}, "holds body 'ball', which has neither a pointshell nor"));
  Hand bad_coupling = hand;
  bad_coupling.coupling.stiffness = -1.0;
  EXPECT_TRUE(refuses(bodies, {bad_coupling}, "stiffness"));
}

}  // namespace
}  // namespace khz::haptic
