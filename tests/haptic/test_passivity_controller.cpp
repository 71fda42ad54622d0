// The time-domain passivity controller (Hannaford & Ryu 2002): its observer against the work of
// known held wrenches over known motions, its damper against the formula, and SafeDevice's
// optional use of it on a wall built to inject energy.

#include <khz/haptic/device/passivity_controller.hpp>
#include <khz/haptic/device/safe_device.hpp>
#include <khz/haptic/device/simulated_operator.hpp>

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

namespace khz::haptic {
namespace {

Pose at(const Eigen::Vector3d& position, double angle_about_z = 0.0) {
  return {position, Eigen::Quaterniond(Eigen::AngleAxisd(angle_about_z, Eigen::Vector3d::UnitZ()))};
}

Wrench wrench(const Eigen::Vector3d& force, const Eigen::Vector3d& torque) {
  Wrench w;
  w.force = force;
  w.torque = torque;
  return w;
}

TEST(PassivityController, ObservesTheWorkOfTheHeldWrenchAndDampsTheDeficitAway) {
  PassivityController controller;
  controller.set_limits(50.0, 0.2);
  constexpr double period = 1e-3;
  // A force of 2 N along +x held while the device moves 1 mm along +x: the simulation gave the
  // hand 2 mJ (E = −2 mJ). A torque of 0.1 N·m about z held while it turns 0.01 rad about z:
  // 1 mJ on the rotational port.
  controller.observe(at({0, 0, 0}), 0.0, Wrench{}, period);
  controller.observe(at({1e-3, 0, 0}, 0.01), 0.002, wrench({2, 0, 0}, {0, 0, 0.1}), period);
  EXPECT_NEAR(controller.translational_energy(), -2e-3, 1e-15);
  EXPECT_NEAR(controller.rotational_energy(), -1e-3, 1e-15);
  // The damper: v = 0.5 m/s over Δt = 2 ms (the device's clock), α = 2e-3 / (2e-3 · 0.25) =
  // 4 N·s/m, opposing v; β = 1e-3 / (2e-3 · 25) = 0.02 N·m·s/rad at ω = 5 rad/s.
  Wrench output = wrench({0, 1, 0}, {0, 0, 0});
  ASSERT_TRUE(controller.damp(output));
  EXPECT_NEAR(output.force.x(), -4.0 * 0.5, 1e-12);
  EXPECT_EQ(output.force.y(), 1.0);
  EXPECT_NEAR(output.torque.z(), -0.02 * 5.0, 1e-12);
  // The limits cap it.
  controller.set_limits(1.0, 0.001);
  output = Wrench{};
  controller.damp(output);
  EXPECT_NEAR(output.force.x(), -1.0 * 0.5, 1e-12);
  EXPECT_NEAR(output.torque.z(), -0.001 * 5.0, 1e-12);
  // Energy the hand puts in (pushing back against the force) pays the deficit back; a surplus
  // damps nothing. Without a clock step the period stands in.
  controller.observe(at({0, 0, 0}, 0.0), 0.002, wrench({2, 0, 0}, {0, 0, 0.1}), period);
  EXPECT_NEAR(controller.translational_energy(), 0.0, 1e-15);
  EXPECT_NEAR(controller.rotational_energy(), 0.0, 1e-15);
  controller.observe(at({-1e-3, 0, 0}), 0.002, wrench({2, 0, 0}, {}), period);
  EXPECT_NEAR(controller.translational_energy(), 2e-3, 1e-15);
  output = Wrench{};
  EXPECT_FALSE(controller.damp(output));
  EXPECT_EQ(output.force, Eigen::Vector3d::Zero());
  // A gap in the readings is not observed; a restart forgets everything.
  controller.interrupt();
  controller.observe(at({1, 0, 0}), 0.003, wrench({100, 0, 0}, {}), period);
  EXPECT_NEAR(controller.translational_energy(), 2e-3, 1e-15);
  controller.restart();
  EXPECT_EQ(controller.translational_energy(), 0.0);
  EXPECT_EQ(controller.rotational_energy(), 0.0);
}

/// A hand pressing a simulated device 2 mm into a wall z ≤ 0 rendered as a spring of
/// `wall_stiffness` sampled at 1 kHz and held (the loop computes F = k·depth from each reading).
/// Colgate's condition: the wall is passive only if the device's and hand's damping (6.5 N·s/m)
/// exceed k T / 2, so a 30 kN/m wall (15 N·s/m) gains energy at every bounce.
struct WallRun {
  double largest_energy = 0.0;   // the device's and hand's kinetic energy, largest (J)
  double late_amplitude = 0.0;   // max − min of z over the last second (m)
  double lowest_observed = 0.0;  // SafeDevice::observed_energy(), lowest (J)
  std::uint64_t damped_writes = 0;
};

WallRun press_wall(double wall_stiffness, bool passivity_control) {
  const Pose pressed = at({0, 0, -2e-3});
  SimulatedOperatorOptions hand;
  hand.initial_pose = at({0, 0, 5e-3});
  hand.start_at_target = false;
  SimulatedOperator device([&](double) { return pressed; }, hand);
  SafetyOptions safety;
  safety.onset_force = std::numeric_limits<double>::infinity();
  safety.passivity_control = passivity_control;
  SafeDevice safe(device, safety);
  safe.open();
  WallRun run;
  double low = INFINITY, high = -INFINITY;
  constexpr int cycles = 3000;
  for (int i = 0; i < cycles; ++i) {
    DeviceState state;
    safe.read(state);
    const double depth = std::max(0.0, -state.pose.position.z());
    safe.write(wrench({0, 0, wall_stiffness * depth}, {0, 0, 0}));
    run.largest_energy = std::max(run.largest_energy, device.kinetic_energy());
    run.lowest_observed = std::min(run.lowest_observed, safe.observed_energy());
    if (i >= cycles - 1000) {
      low = std::min(low, state.pose.position.z());
      high = std::max(high, state.pose.position.z());
    }
  }
  run.late_amplitude = high - low;
  run.damped_writes = safe.statistics().passivity_damped_writes;
  return run;
}

TEST(PassivityController, RestoresStabilityOnAWallThatInjectsEnergy) {
  const WallRun passive = press_wall(3000.0, false);  // k T / 2 = 1.5 < 6.5: passive
  const WallRun active = press_wall(30000.0, false);  // 15 > 6.5: gains energy
  const WallRun controlled = press_wall(30000.0, true);
  const WallRun passive_controlled = press_wall(3000.0, true);
  for (const auto& [name, run] : {std::pair{"passive", passive}, std::pair{"active", active},
                                  std::pair{"controlled", controlled},
                                  std::pair{"passive, controlled", passive_controlled}}) {
    std::printf(
        "%-20s largest kinetic energy %.3e J, late amplitude %.3e m, lowest observer %.3e J, "
        "damped writes %llu\n",
        name, run.largest_energy, run.late_amplitude, run.lowest_observed,
        static_cast<unsigned long long>(run.damped_writes));
  }
  // Without control the stiff wall keeps the device bouncing (a limit cycle of a fifth of a
  // millimetre, held by the device's force limit) and the observer shows the energy it gave;
  // with control it settles (< 10 µm, like the passive wall's), and the observer stays above
  // the uncontrolled one. Sampling and holding makes even the passive wall's port slightly
  // active (Colgate: the device's own damping pays for it), so the controller also acts there.
  EXPECT_GT(active.late_amplitude, 1e-4);
  EXPECT_LT(active.lowest_observed, -1e-3);
  EXPECT_LT(controlled.late_amplitude, 1e-5);
  EXPECT_LT(controlled.late_amplitude, 0.01 * active.late_amplitude);
  EXPECT_GT(controlled.lowest_observed, active.lowest_observed / 5.0);
  EXPECT_GT(controlled.damped_writes, 0u);
  EXPECT_LT(passive.late_amplitude, 1e-5);
  EXPECT_EQ(passive.damped_writes, 0u) << "off by default";
}

}  // namespace
}  // namespace khz::haptic
