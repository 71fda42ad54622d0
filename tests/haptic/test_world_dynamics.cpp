// World's dynamic bodies (issue 20): a box dropped on a floor comes to rest and sleeps without its
// energy ever growing; two bodies colliding in free space keep their momentum; a hand grasps a
// box, carries it and lets it fall; a block pushed by a paddle breaks loose at μ_s m g; a cycle
// allocates nothing; bad set-ups are refused.
#include "hard_case_fixtures.hpp"

#include <khz/contact/field/implicit_shapes.hpp>
#include <khz/haptic/device/null_device.hpp>
#include <khz/haptic/world/world.hpp>
#include <khz/test/allocation_probe.hpp>
#include <khz/test/fixtures.hpp>

#include <gtest/gtest.h>

#include <cmath>

namespace khz::haptic {
namespace {

using test::throws_with_message;

constexpr double g = 9.81;          // m/s²
constexpr double half_side = 0.05;  // m: the 10 cm box and block
constexpr double ball_radius = 0.05;

/// The 10 cm box's surface, points 1 cm apart on its faces, inward normals, in nested levels.
const contact::PointTree& box_shell() {
  static const contact::PointTree tree = hard_cases::nested_tree(
      hard_cases::box_pointshell(Eigen::Vector3d::Zero(), Eigen::Vector3d::Constant(half_side),
                                 0.01),
      24);
  return tree;
}

/// A 5 cm ball's surface, 1,360 points in 3 levels, inward normals.
const contact::PointTree& ball_shell() {
  static const contact::PointTree tree =
      hard_cases::nested_tree(hard_cases::sphere_pointshell(ball_radius, 85 * 16), 85);
  return tree;
}

const contact::ImplicitShape& floor_shape() {
  static const contact::ImplicitShape floor = contact::HalfSpace(Eigen::Vector3d::UnitZ(), 0.0);
  return floor;
}
const contact::ImplicitShape& box_field() {
  static const contact::ImplicitShape box =
      contact::Box(Eigen::Vector3d::Zero(), Eigen::Vector3d::Constant(half_side));
  return box;
}
const contact::ImplicitShape& ball_field() {
  static const contact::ImplicitShape ball = contact::Sphere(Eigen::Vector3d::Zero(), ball_radius);
  return ball;
}

/// k_C = 2,000 N/m per point, L = 10: 20 kN/m at full contact.
contact::ContactOptions contact_options() {
  return hard_cases::contact_options(contact::HapticObject::pointshell);
}

/// A uniform 10 cm cube of mass m about its centre.
RigidInertia cube(double mass) {
  RigidInertia inertia;
  inertia.mass = mass;
  inertia.inertia =
      Eigen::Matrix3d::Identity() * mass * (2.0 * half_side) * (2.0 * half_side) / 6.0;
  return inertia;
}
/// A uniform ball of ball_radius and mass m about its centre.
RigidInertia solid_ball(double mass) {
  RigidInertia inertia;
  inertia.mass = mass;
  inertia.inertia = Eigen::Matrix3d::Identity() * 0.4 * mass * ball_radius * ball_radius;
  return inertia;
}

Body fixed_floor() {
  Body floor;
  floor.name = "floor";
  floor.field = &floor_shape();
  return floor;
}

/// A dynamic box of 1 kg whose centre starts at `centre`, touching with its pointshell and, if
/// `with_field`, its box field too.
Body dynamic_box(const Eigen::Vector3d& centre, bool with_field) {
  Body box;
  box.name = "box";
  box.pose.translation() = centre;
  box.pointshell = &box_shell();
  if (with_field) box.field = &box_field();
  box.dynamics.emplace().inertia = cube(1.0);
  return box;
}

void run(World& world, int cycles) {
  for (int i = 0; i < cycles; ++i) world.cycle(i * 1e-3, (i + 1) * 1e-3, [] { return 0.0; });
}

/// Kinetic plus gravitational energy of a dynamic body (J), height measured along −gravity.
double energy(const FreeBodyMotion& body) {
  return body.kinetic_energy() + body.inertia().mass * g * body.centre().z();
}

// Dropped from 5 cm, the box falls as in free fall, lands, and 1 s after the impact it is still
// (and asleep: then it neither moves nor costs a query). Its energy never rises above the
// start's, and never rises again once the first bounce is over by more than the contact spring
// can hold (the energy it stores at rest, k x²/2 with k x = m g).
TEST(WorldDynamics, ABoxDroppedOnAFloorComesToRestAndSleepsWithoutGainingEnergy) {
  World world({dynamic_box({0, 0, half_side + 0.05}, false), fixed_floor()}, {}, contact_options());
  const FreeBodyMotion& box = *world.motion(0);
  const double start = energy(box);
  // Free fall: the implicit step is exact for constant force up to h g t per step in position.
  run(world, 50);
  EXPECT_NEAR(box.velocity().z(), -g * 0.05, 1e-9);
  EXPECT_NEAR(box.centre().z(), half_side + 0.05 - 0.5 * g * 0.05 * 0.05, g * 1e-3 * 0.05);
  double highest = 0.0;
  int impact = -1;
  for (int i = 50; i < 2500; ++i) {
    world.cycle(i * 1e-3, (i + 1) * 1e-3, [] { return 0.0; });
    highest = std::max(highest, energy(box) - start);
    if (impact < 0 && world.pair_result(0).statistics.points_in_contact > 0) impact = i;
    if (impact >= 0 && i == impact + 1000) {
      EXPECT_LT(box.velocity().norm(), 1e-4)
          << "1 s after the impact " << box.velocity().transpose() << " w "
          << box.angular_velocity().transpose();
      EXPECT_LT(box.angular_velocity().norm() * half_side, 1e-4);
    }
  }
  EXPECT_GT(impact, 100);
  EXPECT_LT(impact, 160) << "free fall from 5 cm takes 101 ms";
  EXPECT_LE(highest, 1e-12) << "the energy never rises above the start's";
  EXPECT_TRUE(world.asleep(0));
  const double rest = box.centre().z();
  EXPECT_NEAR(rest, half_side, 1e-3) << "resting on the floor, pressed in less than a mm";
  run(world, 500);
  EXPECT_EQ(box.centre().z(), rest) << "a sleeping body does not drift";
}

// Two balls collide off-centre in free space (no gravity): linear momentum and angular momentum
// about the origin stay within 1 % of the start's, and the collision did happen.
TEST(WorldDynamics, TwoBodiesCollidingInFreeSpaceKeepTheirMomentum) {
  Body a;
  a.name = "a";
  a.pointshell = &ball_shell();
  a.dynamics.emplace().inertia = solid_ball(1.0);
  Body b;
  b.name = "b";
  b.field = &ball_field();
  b.pose.translation() = Eigen::Vector3d(0.2, 0.03, 0.0);
  b.dynamics = BodyDynamics{solid_ball(2.0), {-0.5, 0.0, 0.0}, {0.0, 0.0, 2.0}};
  World world({a, b}, {}, contact_options());
  DynamicsOptions options;
  options.gravity.setZero();
  world.set_dynamics(options);
  const FreeBodyMotion& first = *world.motion(0);
  const FreeBodyMotion& second = *world.motion(1);
  const Eigen::Vector3d momentum = first.momentum() + second.momentum();
  const Eigen::Vector3d angular = first.angular_momentum() + second.angular_momentum();
  run(world, 600);
  EXPECT_GT(first.velocity().norm(), 0.2) << "b hit a";
  const Eigen::Vector3d momentum_after = first.momentum() + second.momentum();
  const Eigen::Vector3d angular_after = first.angular_momentum() + second.angular_momentum();
  EXPECT_LE((momentum_after - momentum).norm(), 0.01 * momentum.norm());
  EXPECT_LE((angular_after - angular).norm(), 0.01 * angular.norm());
}

/// A hand on a NullDevice (its pose set by the test), behind its safety layer, opened.
struct SetHand {
  SetHand() : safe(device) { safe.open(); }
  NullDevice device;
  SafeDevice safe;
};

CouplingOptions coupling_options() {
  CouplingOptions options;
  options.stiffness = 500.0;
  options.max_rendered_force = 1e3;
  return options;
}

/// Hand 0 holding body 0 through `hand`'s safety layer, grasping with button 0.
Hand hand_holding_body_0(SetHand& hand) {
  Hand holding = hard_cases::holding_body_0(hand.safe, coupling_options());
  holding.grasp_button = 0;
  return holding;
}

/// Bodies 0: a held 5 cm ball above the box (its gripper, kept off the floor by the pair
/// filter); 1: the 1 kg box, dynamic, on 2: the floor.
World gripper_box_and_floor(SetHand& hand, const Eigen::Vector3d& gripper) {
  Body tool;
  tool.name = "gripper";
  tool.pointshell = &ball_shell();
  tool.pose.translation() = gripper;
  hand.device.set_pose(hard_cases::at(gripper));
  return World({tool, dynamic_box({0, 0, half_side}, true), fixed_floor()},
               {hand_holding_body_0(hand)}, contact_options(),
               [](int a, int b) { return !(a == 0 && b == 2); });
}

// Pressing the grasp button while the gripper rests on the box grasps it: the box then rides
// with the gripper at a fixed relative pose, the hand feels its weight (m g down, to 1 %, when
// nothing else touches it), and the pair between the two is no longer queried. Letting go hands
// it back to dynamics: it falls, lands and sleeps on the floor (with friction) again.
TEST(WorldDynamics, AHandGraspsCarriesAndReleasesABody) {
  SetHand hand;
  const Eigen::Vector3d above(0.0, 0.0, 2 * half_side + ball_radius + 0.01);
  World world = gripper_box_and_floor(hand, above);
  // With friction, so that the box, landing a little tilted and off-centre, stops sliding.
  world.set_pair_friction(1, 2, {0.5, 0.4, 1e-4});
  run(world, 400);
  EXPECT_TRUE(world.asleep(1)) << "the box settled on the floor";
  // Lower the gripper 1.5 cm onto the box: it touches (and wakes) the box.
  int cycle = 400;
  const auto hold_at = [&](const Eigen::Vector3d& target, int cycles) {
    hand.device.set_pose(hard_cases::at(target));
    for (int i = 0; i < cycles; ++i, ++cycle) {
      world.cycle(cycle * 1e-3, (cycle + 1) * 1e-3, [] { return 0.0; });
    }
  };
  const Eigen::Vector3d pressing = above - Eigen::Vector3d(0, 0, 0.015);
  hold_at(pressing, 300);
  ASSERT_EQ(world.hand_of(1), -1);
  hand.device.set_buttons(1u);
  hold_at(pressing, 1);
  ASSERT_EQ(world.hand_of(1), 0) << "the button grasped the box";
  const Eigen::Isometry3d in_hand = world.bodies()[0].pose.inverse() * world.bodies()[1].pose;
  // Lift 10 cm: the box rides along, and only its weight is felt (were the gripper–box pair
  // still queried, its contact would be too).
  const Eigen::Vector3d lifted = above + Eigen::Vector3d(0, 0, 0.1);
  hold_at(lifted, 1500);
  const Eigen::Isometry3d carried = world.bodies()[0].pose.inverse() * world.bodies()[1].pose;
  EXPECT_LE((carried.matrix() - in_hand.matrix()).norm(), 1e-12);
  EXPECT_GT(world.bodies()[1].pose.translation().z(), half_side + 0.05) << "lifted";
  EXPECT_NEAR(world.wrench(0).force.z(), -g, 0.01 * g) << "the hand feels the box's weight";
  EXPECT_LE(world.wrench(0).force.head<2>().norm(), 0.01 * g);
  // Let go: the box falls back and comes to rest.
  hand.device.set_buttons(0u);
  hold_at(lifted, 1);
  EXPECT_EQ(world.hand_of(1), -1);
  hold_at(lifted, 2000);
  EXPECT_TRUE(world.asleep(1));
  EXPECT_NEAR(world.motion(1)->centre().z(), half_side, 1e-3);
}

/// A 2 × 6 × 2 cm paddle's surface, points 5 mm apart, symmetric about its centre's planes.
const contact::PointTree& paddle_shell() {
  static const contact::PointTree tree = hard_cases::nested_tree(
      hard_cases::box_pointshell(Eigen::Vector3d::Zero(), Eigen::Vector3d(0.01, 0.03, 0.01), 0.005),
      16);
  return tree;
}

/// The held paddle, 2 mm from the block's −x face, 1.5 cm above the floor, and `hand`'s device
/// at its grasp point.
Body paddle_beside_block(SetHand& hand) {
  Body tool;
  tool.name = "paddle";
  tool.pointshell = &paddle_shell();
  tool.pose.translation() = Eigen::Vector3d(-half_side - 0.01 - 0.002, 0.0, 0.015);
  hand.device.set_pose(hard_cases::at(tool.pose.translation()));
  return tool;
}

// A held paddle pushes the 1 kg block resting on the floor (μ_s = 0.5, μ_k = 0.4) sideways, its
// hand moving on at 2 cm/s: the block does not slide (beyond its anchors' give) until the push
// reaches μ_s m g, within 2 %. The push is horizontal and has no turn about the vertical (the
// paddle's face is flat and centred), but it is 1.5 cm above the floor, so it shifts the load
// towards the block's front edge: the contact still breaks loose only at μ_s times its whole
// normal force.
TEST(WorldDynamics, ABlockPushedOnAFloorSlidesOnlyAtTheStaticFrictionForce) {
  SetHand hand;
  const Body tool = paddle_beside_block(hand);
  World world({tool, dynamic_box({0, 0, half_side}, true), fixed_floor()},
              {hand_holding_body_0(hand)}, contact_options(),
              [](int a, int b) { return !(a == 0 && b == 2); });
  world.set_pair_friction(1, 2, {0.5, 0.4, 1e-4});
  int push = -1, rest = -1;
  for (std::size_t p = 0; p < world.pairs().size(); ++p) {
    const WorldPair& pair = world.pairs()[p];
    if (pair.pointshell == 0 && pair.field == 1) push = static_cast<int>(p);
    if (pair.pointshell == 1 && pair.field == 2) rest = static_cast<int>(p);
  }
  ASSERT_GE(push, 0);
  ASSERT_GE(rest, 0);
  run(world, 500);  // the block settles on the floor
  ASSERT_TRUE(world.asleep(1));
  const double start = world.motion(1)->centre().x();
  double largest_push = 0.0;
  bool slid = false;
  for (int i = 0; i < 4000 && !slid; ++i) {
    const Eigen::Vector3d target = tool.pose.translation() + Eigen::Vector3d(0.02 * i * 1e-3, 0, 0);
    hand.device.set_pose(hard_cases::at(target));
    world.cycle((500 + i) * 1e-3, (501 + i) * 1e-3, [] { return 0.0; });
    largest_push = std::max(largest_push, world.pair_result(push).force.x());
    slid = world.motion(1)->centre().x() - start > 2e-3;
  }
  ASSERT_TRUE(slid) << "pushed 8 cm";
  EXPECT_NEAR(largest_push, 0.5 * 1.0 * g, 0.02 * 0.5 * g);
  // Pushed along, it slides with its whole bottom at μ_k m g.
  EXPECT_EQ(world.pair_result(rest).statistics.points_sliding,
            world.pair_result(rest).statistics.points_in_contact);
}

// A held paddle leaning lightly on a sleeping block wakes it, the block falls asleep again once
// still, and is woken again, over and over. The block's pair with the floor comes first in the
// World's pairs, so in a waking cycle it has already been passed over (the block slept) when
// the paddle's pair wakes the block: the block must not move in that cycle, or it would be
// stepped with no floor under it (and fall g h² = 10 µm each time).
TEST(WorldDynamics, ABodyWokenMidCycleWaitsForAllItsContactsBeforeItMoves) {
  SetHand hand;
  const Body tool = paddle_beside_block(hand);
  Hand holding = hand_holding_body_0(hand);
  holding.body = 2;
  World world({dynamic_box({0, 0, half_side}, true), fixed_floor(), tool}, {holding},
              contact_options(), [](int a, int b) { return std::min(a, b) != 1 || a + b != 3; });
  world.set_pair_friction(0, 1, {0.5, 0.4, 1e-4});
  ASSERT_EQ(world.pairs()[0].pointshell, 0);
  ASSERT_EQ(world.pairs()[0].field, 1) << "the block–floor pair is queried first";
  run(world, 500);
  ASSERT_TRUE(world.asleep(0));
  const double resting = world.motion(0)->centre().z();
  // The paddle moves 2.2 mm to lean 0.2 mm into the block's side, and holds there for 2 s.
  hand.device.set_pose(hard_cases::at(tool.pose.translation() + Eigen::Vector3d(0.0022, 0, 0)));
  double lowest = resting;
  int wakes = 0;
  bool was_asleep = true;
  for (int i = 500; i < 2500; ++i) {
    world.cycle(i * 1e-3, (i + 1) * 1e-3, [] { return 0.0; });
    lowest = std::min(lowest, world.motion(0)->centre().z());
    wakes += was_asleep && !world.asleep(0) ? 1 : 0;
    was_asleep = world.asleep(0);
  }
  EXPECT_GE(wakes, 3) << "the paddle keeps waking the block";
  EXPECT_LE(resting - lowest, 1e-6) << "woken, the block never fell through its floor contact";
  std::printf("woken %d times, lowest %.3g m below its rest\n", wakes, resting - lowest);
}

// With dynamic bodies, friction and a grasp, a cycle allocates nothing (nor do grasp() and
// release()).
TEST(WorldDynamics, ACycleAllocatesNothing) {
  SetHand hand;
  const Eigen::Vector3d on_box(0.0, 0.0, 2 * half_side + ball_radius - 0.005);
  World world = gripper_box_and_floor(hand, on_box);
  world.set_pair_friction(1, 2, {0.5, 0.4, 1e-4});
  run(world, 200);
  ASSERT_GT(world.body_wrench(1).statistics.points_in_contact, 0);
  test::allocation_count = 0;
  for (int i = 200; i < 300; ++i) world.cycle(i * 1e-3, (i + 1) * 1e-3, [] { return 0.0; });
  EXPECT_EQ(world.grasp(0), 1);
  for (int i = 300; i < 350; ++i) world.cycle(i * 1e-3, (i + 1) * 1e-3, [] { return 0.0; });
  EXPECT_EQ(world.release(0), 1);
  for (int i = 350; i < 400; ++i) world.cycle(i * 1e-3, (i + 1) * 1e-3, [] { return 0.0; });
  EXPECT_EQ(test::allocation_count, 0u);
}

// A free body placed somewhere (to replay a recorded state) is at rest there, awake, and a probe
// queries its pairs; a fixed, a grasped or an unknown body, or a pose that is not finite, is
// refused and nothing moves.
TEST(WorldDynamics, AFreeBodyPlacedForAProbeIsQueriedWhereItWasPut) {
  SetHand hand;
  const Eigen::Vector3d on_box(0.0, 0.0, 2 * half_side + ball_radius - 0.005);
  World world = gripper_box_and_floor(hand, on_box);
  run(world, 400);
  Eigen::Isometry3d sunk = Eigen::Isometry3d::Identity();
  sunk.translation() = Eigen::Vector3d(0.1, 0.0, half_side - 0.001);  // 1 mm into the floor
  ASSERT_EQ(world.grasp(0), 1);
  EXPECT_FALSE(world.place_free_body(1, sunk)) << "grasped";
  ASSERT_EQ(world.release(0), 1);
  EXPECT_FALSE(world.place_free_body(2, sunk)) << "the floor is fixed";
  EXPECT_FALSE(world.place_free_body(7, sunk));
  Eigen::Isometry3d broken = sunk;
  broken.translation().x() = std::nan("");
  EXPECT_FALSE(world.place_free_body(1, broken));

  ASSERT_TRUE(world.place_free_body(1, sunk));
  EXPECT_FALSE(world.asleep(1));
  EXPECT_EQ(world.motion(1)->velocity(), Eigen::Vector3d::Zero());
  EXPECT_EQ(world.bodies()[1].pose.translation(), sunk.translation());
  const Pose grasps[] = {hard_cases::at(on_box + Eigen::Vector3d(0, 0, 0.05))};
  ASSERT_TRUE(world.probe(grasps));
  // The floor pushes the sunk box up with L k_C × 1 mm = 20 N (its 100 bottom points, ℓ > L).
  EXPECT_NEAR(world.body_wrench(1).force.z(), 20.0, 0.01 * 20.0);
}

TEST(WorldDynamics, RefusesBadSetUpsNamingTheBody) {
  SetHand hand;
  const auto refuses = [](std::vector<Body> bodies, std::vector<Hand> hands, const char* message) {
    return throws_with_message<Error>(
        [&] { World world(std::move(bodies), std::move(hands), contact_options()); }, message);
  };
  Body weightless = dynamic_box({0, 0, 1}, false);
  weightless.dynamics->inertia.mass = 0.0;
  EXPECT_TRUE(refuses({weightless, fixed_floor()}, {}, "World: body 'box': RigidInertia: mass"));
  Body tool;
  tool.name = "tool";
  tool.pointshell = &ball_shell();
  tool.dynamics.emplace().inertia = solid_ball(1.0);
  EXPECT_TRUE(refuses({tool, fixed_floor()}, {hand_holding_body_0(hand)},
                      "hand 0 holds body 'tool', which is dynamic"));
  tool.dynamics.reset();
  Hand same_button = hand_holding_body_0(hand);
  SafetyOptions safety;
  safety.index_button = 0;
  SafeDevice indexed(hand.device, safety);
  same_button.device = &indexed;
  EXPECT_TRUE(refuses({tool, fixed_floor()}, {same_button},
                      "hand 0's grasp button 0 must be -1 or a bit index in [0, 31] other than"));
  EXPECT_TRUE(refuses({fixed_floor(), fixed_floor()}, {}, "World: no moving body can touch"));
  World world({dynamic_box({0, 0, 1}, false), fixed_floor()}, {}, contact_options());
  DynamicsOptions options;
  options.time_step = 0.0;
  EXPECT_TRUE(throws_with_message<Error>([&] { world.set_dynamics(options); },
                                         "DynamicsOptions: time_step must be finite and > 0"));
  EXPECT_EQ(world.motion(1), nullptr) << "the floor is not dynamic";
  EXPECT_EQ(world.grasp(0), -1) << "no hand";
  EXPECT_EQ(world.release(0), 0);
}

}  // namespace
}  // namespace khz::haptic
