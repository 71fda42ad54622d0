#include "hard_case_fixtures.hpp"

#include <khz/contact/field/implicit_shapes.hpp>
#include <khz/haptic/cycle/contact_scene.hpp>
#include <khz/haptic/cycle/haptic_cycle.hpp>
#include <khz/haptic/device/simulated_operator.hpp>

#include <gtest/gtest.h>

#include <cmath>

namespace khz::haptic {
namespace {

constexpr double ball_radius = 0.05;  // m

/// A 5 cm ball sampled by 5,440 near-uniform points in 4 levels, inward normals.
const contact::PointTree& ball() {
  static const contact::PointTree tree =
      hard_cases::nested_tree(hard_cases::sphere_pointshell(ball_radius, 85 * 64), 85);
  return tree;
}

Pose at(const Eigen::Vector3d& position) {
  Pose p;
  p.position = position;
  return p;
}

TEST(HapticCycle, AHandPressingABallOnAFloorFeelsItWithoutPenetratingOrGainingEnergy) {
  // The hand's anchor moves from 5 cm above contact to 3 cm below the floor in 0.5 s and holds:
  // the device should stop at the floor, render up to its 8.5 N, and settle.
  const contact::ImplicitShape floor = contact::HalfSpace(Eigen::Vector3d::UnitZ(), 0.0);
  SimulatedOperatorOptions hand;
  SimulatedOperator device(keyframe_target({{0.0, at({0.0, 0.0, ball_radius + 0.05})},
                                            {0.5, at({0.0, 0.0, ball_radius - 0.03})}}),
                           hand);
  SafeDevice safe(device);
  safe.open();
  contact::ContactOptions contact_options;
  contact_options.haptic_object = contact::HapticObject::pointshell;
  contact_options.stiffness = 2000.0;  // ×L = 10 at full contact: 20 kN/m, stiffer than k_VC
  PointshellFieldScene scene(ball(), floor, contact_options, Eigen::Vector3d::Zero(),
                             Eigen::Isometry3d::Identity());
  CouplingOptions coupling_options;
  coupling_options.stiffness = 500.0;
  coupling_options.max_rendered_force = hand.capabilities.max_force;
  VirtualCoupling coupling(coupling_options, at({0.0, 0.0, ball_radius + 0.05}));
  HapticCycle cycle(safe, coupling, scene);

  double deepest = 0.0, strongest = 0.0, energy_late = 0.0, energy_peak_late = 0.0;
  for (int i = 0; i < 3000; ++i) {
    const double now = i * 1e-3;
    const CycleRecord& r = cycle.run(now, now + 1e-3, [&] { return now + 1e-4; });
    ASSERT_TRUE(r.device_valid && r.contact_valid && r.coupling_valid) << "cycle " << i;
    ASSERT_TRUE(r.simulation.position.allFinite() && r.rendered.force.allFinite());
    deepest = std::max(deepest, ball_radius - r.simulation.position.z());
    strongest = std::max(strongest, r.rendered.force.norm());
    if (i >= 2000) {
      const double e = device.kinetic_energy();
      energy_late += e / 1000.0;
      energy_peak_late = std::max(energy_peak_late, e);
    }
  }
  const CycleRecord& last = cycle.record();
  // The ball rests on the floor: penetration well below a millimetre (the contact is ~40× stiffer
  // than the coupling), while the device sinks below it (virtual coupling, §3.1.1) until the
  // rendered spring k_VC (x_s − x_m) balances the hand's spring k_h (x_m − anchor).
  EXPECT_LT(deepest, 1e-3);
  EXPECT_GT(deepest, 0.0);
  EXPECT_GT(last.contact.force.z(), 1.0) << "the floor holds the ball up";
  const double sunk = last.simulation.position.z() - device.pose().position.z();
  EXPECT_GT(sunk, 0.005) << "the manipulandum is below the ball it holds";
  EXPECT_NEAR(last.rendered.force.z(), coupling_options.stiffness * sunk, 1e-6);
  const double hand_force =
      hand.hand.stiffness * (device.pose().position.z() - device.target_pose().position.z());
  EXPECT_NEAR(last.rendered.force.z(), hand_force, 0.02 * hand_force);
  EXPECT_LE(strongest, hand.capabilities.max_force * (1.0 + 1e-12));
  // At rest: the device does not oscillate against the rendered wall.
  EXPECT_LT(energy_peak_late, 1e-6) << "mean " << energy_late;
}

}  // namespace
}  // namespace khz::haptic
