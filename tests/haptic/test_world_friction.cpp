// Friction on the World's dynamic bodies against the closed forms of Coulomb's law (issue 20's
// verification): a block on an incline sticks below tan θ = μ_s and above it slides with
// acceleration g (sin θ − μ_k cos θ); a disc spinning flat on a floor stops in the time uniform
// pressure and μ_k predict, 3 R ω₀ / (4 μ_k g).
#include "hard_case_fixtures.hpp"

#include <khz/contact/field/implicit_shapes.hpp>
#include <khz/haptic/world/world.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <vector>

namespace khz::haptic {
namespace {

constexpr double g = 9.81;  // m/s², DynamicsOptions' default
// The block: 10 × 10 × 2 cm. A block on an incline presses its downhill edge harder; past
// tan θ = side / (3 height) its uphill edge lifts off the (penalty-soft) contact, and a cube would
// be past that at tan θ = 1/3, rocking as its lifted points lose their anchors.
constexpr double half_side = 0.05, half_height = 0.01;  // m
constexpr double static_coefficient = 0.5, kinetic_coefficient = 0.4;

/// k_C = 2,000 N/m per point, L = 10.
contact::ContactOptions contact_options() {
  return hard_cases::contact_options(contact::HapticObject::pointshell);
}

contact::FrictionOptions friction() {
  contact::FrictionOptions options;
  options.static_coefficient = static_coefficient;
  options.kinetic_coefficient = kinetic_coefficient;
  options.stick_distance = 1e-4;  // the plane is analytic: no voxel for the default
  return options;
}

/// The block's surface, points 1 cm apart on its faces, inward normals, nested levels.
const contact::PointTree& block_shell() {
  static const contact::PointTree tree = hard_cases::nested_tree(
      hard_cases::box_pointshell(Eigen::Vector3d::Zero(),
                                 Eigen::Vector3d(half_side, half_side, half_height), 0.01),
      24);
  return tree;
}

void run(World& world, int first, int cycles) {
  for (int i = first; i < first + cycles; ++i) {
    world.cycle(i * 1e-3, (i + 1) * 1e-3, [] { return 0.0; });
  }
}

/// A 1 kg block resting on a plane tilted by `angle` about y (downhill: +x), pressed in as deep
/// as its weight holds it (m g cos θ / (L k_C): L/ℓ makes the whole contact's stiffness L k_C),
/// and the World of the two with friction μ_s = 0.5, μ_k = 0.4 between them.
struct Incline {
  explicit Incline(double angle)
      : normal(std::sin(angle), 0.0, std::cos(angle)),
        downhill(std::cos(angle), 0.0, -std::sin(angle)),
        plane(contact::HalfSpace(normal, 0.0)),
        world(bodies(), {}, contact_options()) {
    world.set_pair_friction(0, 1, friction());
  }

  std::vector<Body> bodies() const {
    Body block;
    block.name = "block";
    block.pointshell = &block_shell();
    block.pose.linear() =
        Eigen::AngleAxisd(std::atan2(normal.x(), normal.z()), Eigen::Vector3d::UnitY())
            .toRotationMatrix();
    const contact::ContactOptions options = contact_options();
    block.pose.translation() =
        (half_height - g * normal.z() / (options.scaling_count * options.stiffness)) * normal;
    RigidInertia& inertia = block.dynamics.emplace().inertia;
    inertia.mass = 1.0;
    inertia.inertia.diagonal() << (half_side * half_side + half_height * half_height) / 3.0,
        (half_side * half_side + half_height * half_height) / 3.0,
        2.0 * half_side * half_side / 3.0;
    Body slope;
    slope.name = "slope";
    slope.field = &plane;
    return {block, slope};
  }

  double along_slope() const { return world.motion(0)->centre().dot(downhill); }
  double speed_down_slope() const { return world.motion(0)->velocity().dot(downhill); }

  Eigen::Vector3d normal, downhill;
  contact::ImplicitShape plane;
  World world;
};

// Below the friction angle (tan θ = 0.4 < μ_s = 0.5) the block stays where it was put, but for
// the anchors' give (δ tan θ / μ_s, 0.08 mm) and the first cycle's step (its points anchor, so
// nothing holds it yet), and falls asleep; above it (30°, tan θ = 0.58)
// it slides with g (sin θ − μ_k cos θ) = 1.507 m/s² within 2 %, measured from its speed between
// 0.1 and 0.4 s.
TEST(WorldFriction, ABlockOnAnInclineSticksBelowTheFrictionAngleAndSlidesAboveIt) {
  Incline gentle(std::atan(0.4));
  const double start = gentle.along_slope();
  run(gentle.world, 0, 1000);
  EXPECT_TRUE(gentle.world.asleep(0));
  EXPECT_LT(std::abs(gentle.along_slope() - start), 1.5 * friction().stick_distance);

  const double angle = std::numbers::pi / 6.0;
  Incline steep(angle);
  run(steep.world, 0, 100);
  const double early = steep.speed_down_slope();
  run(steep.world, 100, 300);
  const double late = steep.speed_down_slope();
  const double expected = g * (std::sin(angle) - kinetic_coefficient * std::cos(angle));
  const double measured = (late - early) / 0.3;
  EXPECT_NEAR(measured, expected, 0.02 * expected);
  EXPECT_EQ(steep.world.pair_result(0).statistics.points_sliding,
            steep.world.pair_result(0).statistics.points_in_contact);
  std::printf("incline 30 deg: %.4f m/s^2 against %.4f (%+.2f %%)\n", measured, expected,
              100.0 * (measured / expected - 1.0));
}

// A 1 kg disc of radius R = 10 cm lying on a floor, spinning at ω₀ = 10 rad/s: under uniform
// pressure each ring r dr carries μ_k m g 2 r dr / R² of friction at arm r, a torque of
// (2/3) μ_k m g R against I = m R² / 2, so it stops after 3 R ω₀ / (4 μ_k g) = 191 ms. Its
// pointshell samples its bottom on a 5 mm grid; the stop is the first cycle its spin falls
// below 1 % of ω₀, within 5 % of the prediction.
TEST(WorldFriction, ASpinningDiscStopsInTheTimeDistributedCoulombFrictionPredicts) {
  constexpr double radius = 0.1, thickness = 0.01, spin = 10.0;
  std::vector<Eigen::Vector3d> points;
  for (double x = -radius + 0.0025; x < radius; x += 0.005) {
    for (double y = -radius + 0.0025; y < radius; y += 0.005) {
      if (x * x + y * y < radius * radius) points.emplace_back(x, y, -0.5 * thickness);
    }
  }
  contact::Pointshell bottom;
  bottom.points.resize(static_cast<Eigen::Index>(points.size()), 3);
  bottom.normals.resize(bottom.points.rows(), 3);
  for (std::size_t i = 0; i < points.size(); ++i) {
    bottom.points.row(static_cast<Eigen::Index>(i)) = points[i].transpose();
    bottom.normals.row(static_cast<Eigen::Index>(i)) << 0.0, 0.0, 1.0;
  }
  bottom.level_ends = {bottom.points.rows()};
  const contact::PointTree shell = hard_cases::nested_tree(bottom, 20);
  const contact::ImplicitShape floor = contact::HalfSpace(Eigen::Vector3d::UnitZ(), 0.0);

  Body disc;
  disc.name = "disc";
  disc.pointshell = &shell;
  // Pressed in as deep as its weight holds it (m g / (L k_C): L/ℓ makes the whole contact's
  // stiffness L k_C), so that it spins on a steady load from the start.
  const contact::ContactOptions options = contact_options();
  disc.pose.translation() =
      Eigen::Vector3d(0.0, 0.0, 0.5 * thickness - g / (options.scaling_count * options.stiffness));
  BodyDynamics& dynamics = disc.dynamics.emplace();
  dynamics.angular_velocity = Eigen::Vector3d(0.0, 0.0, spin);
  dynamics.inertia.mass = 1.0;
  dynamics.inertia.inertia.diagonal() << radius * radius / 4.0 + thickness * thickness / 12.0,
      radius * radius / 4.0 + thickness * thickness / 12.0, radius * radius / 2.0;
  Body ground;
  ground.name = "floor";
  ground.field = &floor;
  World world({disc, ground}, {}, options);
  world.set_pair_friction(0, 1, friction());
  int stopped = -1;
  for (int i = 0; i < 500 && stopped < 0; ++i) {
    world.cycle(i * 1e-3, (i + 1) * 1e-3, [] { return 0.0; });
    if (world.motion(0)->angular_velocity().z() < 0.01 * spin) stopped = i + 1;
  }
  const double expected = 3.0 * radius * spin / (4.0 * kinetic_coefficient * g);
  ASSERT_GT(stopped, 0) << "still spinning after 0.5 s";
  EXPECT_NEAR(stopped * 1e-3, expected, 0.05 * expected);
  std::printf("spinning disc stopped after %.3f s against %.3f s (%+.2f %%)\n", stopped * 1e-3,
              expected, 100.0 * (stopped * 1e-3 / expected - 1.0));
}

}  // namespace
}  // namespace khz::haptic
