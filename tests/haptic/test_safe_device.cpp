// The safety layer: clamping, the watchdog, disconnects, workspace scaling and indexing.

#include <khz/haptic/device/null_device.hpp>
#include <khz/haptic/device/safe_device.hpp>
#include <khz/haptic/device/simulated_operator.hpp>
#include <khz/test/allocation_probe.hpp>
#include <khz/test/fixtures.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>

namespace khz::haptic {
namespace {

constexpr double nan = std::numeric_limits<double>::quiet_NaN();
constexpr double infinity = std::numeric_limits<double>::infinity();

Wrench wrench(const Eigen::Vector3d& force,
              const Eigen::Vector3d& torque = Eigen::Vector3d::Zero()) {
  Wrench w;
  w.force = force;
  w.torque = torque;
  return w;
}

/// A NullDevice behind a SafeDevice, opened, with one good read done.
struct Rig {
  explicit Rig(const SafetyOptions& options = {}, const WorkspaceMapping& mapping = {},
               DeviceCapabilities capabilities = NullDevice::default_capabilities())
      : device(std::move(capabilities)), safe(device, options, mapping) {
    safe.open();
    cycle();
  }
  /// One read and one write; returns what reached the device.
  Wrench cycle(const Wrench& w = {}) {
    safe.read(state);
    safe.write(w);
    return device.last_written();
  }
  NullDevice device;
  SafeDevice safe;
  DeviceState state;
};

TEST(SafeDevice, ClampingKeepsTheDirection) {
  Rig rig;  // 10 N, 1 N·m
  const Wrench out = rig.cycle(wrench({30, 40, 0}, {0, 0, -5}));
  EXPECT_LT((out.force - Eigen::Vector3d(6, 8, 0)).norm(), 1e-12);
  EXPECT_LT((out.torque - Eigen::Vector3d(0, 0, -1)).norm(), 1e-12);
  EXPECT_EQ(rig.safe.last_write_events(), safety_clamped_force | safety_clamped_torque);
  EXPECT_EQ(rig.safe.statistics().clamped_writes, 1u);

  // Below the limits nothing changes, bit for bit.
  const Wrench small = wrench({1.0 / 3.0, -2, 0.1}, {0.2, 0, 1.0 / 7.0});
  const Wrench same = rig.cycle(small);
  EXPECT_EQ(same.force, small.force);
  EXPECT_EQ(same.torque, small.torque);
  EXPECT_EQ(rig.safe.last_write_events(), 0u);

  // Options only tighten; huge finite values keep their direction too.
  rig.safe.set_options({.max_force = 2.0, .max_torque = 50.0});
  const Wrench tight = rig.cycle(wrench({1e300, -1e300, 0}, {0, 3, 4}));
  EXPECT_NEAR(tight.force.norm(), 2.0, 1e-12);
  EXPECT_NEAR(tight.force.x(), -tight.force.y(), 1e-12);
  EXPECT_LT((tight.torque - Eigen::Vector3d(0, 0.6, 0.8)).norm(), 1e-12);  // device's 1 N·m
}

/// One cycle of the rig from a stack frame `Padding` bytes deeper than the caller's, so the
/// safety layer's locals sit at another address.
template <int Padding>
[[gnu::noinline]] Wrench cycle_deeper(Rig& rig, const Wrench& w) {
  char padding[Padding];
  asm volatile("" : : "r"(padding) : "memory");  // keeps the array, and so the deeper frame
  return rig.cycle(w);
}

TEST(SafeDevice, WhetherToClampDependsOnTheWrenchNotOnItsAddress) {
  // A force within an ulp of the 10 N limit, met in a bundled scene after the coupling had
  // clamped it to 10 N by its own norm. Its magnitude rounds to 10 N, so it passes unchanged,
  // from any stack depth. Eigen's stableNorm() sums a Vector3d in an order set by its address
  // (it splits at the first SIMD-aligned coefficient): built with -ffp-contract=off on an
  // AVX-512 machine, it called this force 10 N from one caller's frame and 10.000000000000002 N
  // from another's, so the same scene clamped in one build and not in the other.
  const Wrench w = wrench({0x1.a6afe861c025p+0, -0x1.e8be73e00cc24p+0, 0x1.35a37632b2f99p+3});
  Rig rig;
  const auto passes_unchanged = [&](const Wrench& out) {
    return out.force == w.force && rig.safe.last_write_events() == 0u;
  };
  EXPECT_TRUE(passes_unchanged(cycle_deeper<1>(rig, w)));
  EXPECT_TRUE(passes_unchanged(cycle_deeper<17>(rig, w)));
  EXPECT_TRUE(passes_unchanged(cycle_deeper<33>(rig, w)));
  EXPECT_TRUE(passes_unchanged(cycle_deeper<49>(rig, w)));
  EXPECT_TRUE(passes_unchanged(cycle_deeper<65>(rig, w)));
  EXPECT_TRUE(passes_unchanged(cycle_deeper<81>(rig, w)));
}

TEST(SafeDevice, ForceOnlyDevicesGetNoTorque) {
  DeviceCapabilities capabilities = NullDevice::default_capabilities();
  capabilities.output_dof = 3;
  Rig rig({}, {}, capabilities);
  const Wrench out = rig.cycle(wrench({1, 0, 0}, {0.5, 0, 0}));
  EXPECT_EQ(out.force, Eigen::Vector3d(1, 0, 0));
  EXPECT_EQ(out.torque, Eigen::Vector3d::Zero());
}

TEST(SafeDevice, NothingIsRenderedBeforeTheFirstGoodRead) {
  NullDevice device;
  SafeDevice safe(device);
  safe.open();
  safe.write(wrench({1, 0, 0}));
  EXPECT_EQ(device.last_written().force, Eigen::Vector3d::Zero());
  EXPECT_EQ(safe.last_write_events(), safety_zeroed_read_failure);
}

TEST(SafeDevice, InvalidInputZeroesTheSameCycleAndRecovers) {
  Rig rig;
  const Wrench push = wrench({3, 0, 0}, {0, 0.1, 0});
  rig.device.set_pose(Pose{Eigen::Vector3d(0.01, 0.02, 0.03), Eigen::Quaterniond::Identity()});
  EXPECT_EQ(rig.cycle(push).force, push.force);
  const Eigen::Vector3d good_position = rig.state.pose.position;

  Pose broken;
  broken.position = Eigen::Vector3d(0, nan, 0);
  rig.device.set_pose(broken);
  EXPECT_FALSE(rig.safe.read(rig.state));
  EXPECT_FALSE(rig.state.valid);
  EXPECT_EQ(rig.state.pose.position, good_position);  // the last good pose, marked invalid
  rig.safe.write(push);
  EXPECT_EQ(rig.device.last_written().force, Eigen::Vector3d::Zero());
  EXPECT_EQ(rig.device.last_written().torque, Eigen::Vector3d::Zero());
  EXPECT_EQ(rig.safe.last_write_events(), safety_zeroed_read_failure);

  broken.position.setZero();
  broken.orientation.coeffs() << 0, 0, 0, 2;  // not a unit quaternion
  rig.device.set_pose(broken);
  EXPECT_EQ(rig.cycle(push).force, Eigen::Vector3d::Zero());
  EXPECT_EQ(rig.safe.statistics().invalid_inputs, 2u);
  EXPECT_EQ(rig.safe.statistics().zeroed_writes, 2u);

  // Back, but the device may have come back inside something: nothing while the force asked
  // for exceeds onset_force (1 N), then at once (no ramp configured).
  rig.device.set_pose(Pose{});
  EXPECT_EQ(rig.cycle(push).force, Eigen::Vector3d::Zero());
  EXPECT_TRUE(rig.state.valid);
  EXPECT_EQ(rig.safe.last_write_events(), safety_waiting_for_small_force);
  const Wrench light = wrench({0.6, 0.8, 0});  // exactly 1 N
  EXPECT_EQ(rig.cycle(light).force, light.force);
  EXPECT_EQ(rig.cycle(push).force, push.force);
  EXPECT_EQ(rig.safe.statistics().zeroed_writes, 2u);  // waiting is not a fault
}

TEST(SafeDevice, WaitsForASmallForceAfterOpeningAndNotAfterADeadlineMiss) {
  NullDevice device;
  SafeDevice safe(device, {.deadline_tolerance = 0.0, .onset_force = 2.0});
  safe.open();
  DeviceState state;
  const Wrench push = wrench({0, 0, -5});
  const auto cycle = [&](const Wrench& w) {
    safe.begin_cycle(1.0);
    safe.read(state);
    safe.write(w);
    safe.end_cycle(1.0);
    return device.last_written().force;
  };
  // Opened inside an object: the 5 N push is held back for as long as it lasts.
  for (int i = 0; i < 100; ++i) EXPECT_EQ(cycle(push), Eigen::Vector3d::Zero());
  EXPECT_EQ(safe.last_write_events(), safety_waiting_for_small_force);
  EXPECT_EQ(cycle(wrench({0, 0, -2})), Eigen::Vector3d(0, 0, -2));  // at the threshold: on
  EXPECT_EQ(cycle(push), push.force);

  // A missed deadline neither zeroes nor waits: the push goes on.
  safe.begin_cycle(1.0);
  safe.read(state);
  safe.write(push);
  safe.end_cycle(2.0);
  EXPECT_EQ(cycle(push), push.force);
  EXPECT_EQ(safe.last_write_events(), safety_after_deadline_miss);
  EXPECT_EQ(cycle(push), push.force);

  // Infinity turns the wait off.
  SafeDevice eager(device, {.onset_force = infinity});
  eager.open();
  eager.read(state);
  eager.write(push);
  EXPECT_EQ(device.last_written().force, push.force);
}

TEST(SafeDevice, TheWaitForASmallForceAlsoWaitsForThePendingWrench) {
  NullDevice device;
  WorkspaceMapping doubled;
  doubled.force_scale = 2.0;
  doubled.torque_scale = 2.0;
  SafeDevice safe(device, {.onset_force = 1.0, .onset_torque = 0.1}, doubled);
  safe.open();
  DeviceState state;
  const auto cycle = [&](const Wrench& w, const Wrench& pending) {
    safe.read(state);
    safe.write(w, pending);
    return device.last_written();
  };
  const Wrench push = wrench({0.1, 0, 0});
  // Nothing asked for yet, but 0.6 virtual N pending is 1.2 device N: still waiting; so for a
  // NaN, and for 0.06 virtual N·m of torque pending (0.12 device N·m).
  EXPECT_EQ(cycle(Wrench{}, wrench({0.6, 0, 0})).force, Eigen::Vector3d::Zero());
  EXPECT_EQ(safe.last_write_events(), safety_waiting_for_small_force);
  EXPECT_EQ(cycle(push, wrench({nan, 0, 0})).force, Eigen::Vector3d::Zero());
  EXPECT_EQ(cycle(push, wrench({0.5, 0, 0}, {0, 0.06, 0})).force, Eigen::Vector3d::Zero());
  EXPECT_EQ(safe.last_write_events(), safety_waiting_for_small_force);
  // A torque asked for above the threshold waits too.
  EXPECT_EQ(cycle(wrench({0.1, 0, 0}, {0, 0, 0.06}), Wrench{}).torque, Eigen::Vector3d::Zero());
  // 0.5 N and 0.05 N·m pending are the thresholds: output resumes, and from then on the pending
  // wrench does not matter.
  EXPECT_EQ(cycle(push, wrench({0.5, 0, 0}, {0, 0.05, 0})).force, Eigen::Vector3d(0.2, 0, 0));
  EXPECT_EQ(cycle(push, wrench({100, 0, 0}, {0, 100, 0})).force, Eigen::Vector3d(0.2, 0, 0));
  EXPECT_EQ(safe.last_write_events(), 0u);

  // A 3-DOF output device renders no torque, so none is waited for.
  DeviceCapabilities forces_only = NullDevice::default_capabilities();
  forces_only.output_dof = 3;
  NullDevice pen(forces_only);
  SafeDevice three(pen, {.onset_force = 1.0, .onset_torque = 0.1});
  three.open();
  three.read(state);
  three.write(push, wrench({0, 0, 0}, {0, 5, 0}));
  EXPECT_EQ(pen.last_written().force, push.force);
}

TEST(SafeDevice, NonFiniteOutputNeverReachesTheDevice) {
  Rig rig;
  for (const Wrench& bad : {wrench({nan, 0, 0}), wrench({1, 0, 0}, {0, 0, INFINITY})}) {
    EXPECT_EQ(rig.cycle(bad).force, Eigen::Vector3d::Zero());
    EXPECT_EQ(rig.safe.last_write_events(), safety_zeroed_invalid_output);
  }
  EXPECT_EQ(rig.safe.statistics().invalid_outputs, 2u);
  EXPECT_EQ(rig.cycle(wrench({1, 0, 0})).force, Eigen::Vector3d(1, 0, 0));
}

TEST(SafeDevice, ADeadlineMissNeitherZeroesNorJumps) {
  // Without a ramp the write after a miss is the fresh wrench, as if nothing had happened: a drop
  // to zero would be a jolt, and the hand would sink into what it was pressing.
  Rig rig({.deadline_tolerance = 1e-4});
  const Wrench push = wrench({2, 0, 0});
  const auto timed_cycle = [&](Rig& r, const Wrench& w, double deadline, double end) {
    r.safe.begin_cycle(deadline);
    const Wrench out = r.cycle(w);
    r.safe.end_cycle(end);
    return out;
  };
  EXPECT_EQ(timed_cycle(rig, push, 1.000, 1.00005).force, push.force);  // late but within tolerance
  EXPECT_EQ(rig.safe.statistics().deadline_misses, 0u);
  EXPECT_EQ(timed_cycle(rig, push, 1.001, 1.0015).force, push.force);  // this one misses...
  EXPECT_EQ(rig.safe.statistics().deadline_misses, 1u);
  EXPECT_EQ(timed_cycle(rig, push, 1.002, 1.002).force, push.force);  // ...and output goes on
  EXPECT_EQ(rig.safe.last_write_events(), safety_after_deadline_miss);
  EXPECT_EQ(timed_cycle(rig, push, 1.004, nan).force, push.force);  // a NaN clock is a miss
  EXPECT_EQ(rig.safe.statistics().deadline_misses, 2u);
  EXPECT_EQ(rig.safe.statistics().zeroed_writes, 0u);
  rig.safe.end_cycle(100.0);  // without begin_cycle: nothing
  EXPECT_EQ(rig.safe.statistics().deadline_misses, 2u);

  // With a ramp of N the writes after a miss move from the output the device held through the
  // late cycle to the fresh wrench in N equal steps.
  Rig ramped({.deadline_tolerance = 1e-4, .ramp_cycles = 4});
  for (int k = 0; k < 5; ++k) ramped.cycle(push);              // past the start-up ramp
  const Wrench held = timed_cycle(ramped, push, 2.000, 2.01);  // late: 2 N held for 10 ms
  EXPECT_EQ(held.force, push.force);
  const Wrench fresh = wrench({-1, 3, 0}, {0, 0, 0.4});
  for (int k = 1; k <= 5; ++k) {
    const double factor = std::min(k, 4) / 4.0;
    const Wrench out = ramped.cycle(fresh);
    EXPECT_NEAR((out.force - (push.force + factor * (fresh.force - push.force))).norm(), 0.0, 1e-12)
        << k;
    EXPECT_NEAR((out.torque - factor * fresh.torque).norm(), 0.0, 1e-12) << k;
    EXPECT_EQ((ramped.safe.last_write_events() & safety_ramping) != 0, k < 4) << k;
  }
  EXPECT_EQ(ramped.safe.statistics().zeroed_writes, 0u);
}

TEST(SafeDevice, OutputRampsUpAfterAZeroedWrite) {
  Rig rig({.ramp_cycles = 4});
  const Wrench push = wrench({4, 0, 0}, {0, 0, 0.8});
  for (int round = 0; round < 2; ++round) {
    rig.cycle(wrench({nan, 0, 0}));  // a fault (re)starts the ramp
    for (int k = 1; k <= 5; ++k) {
      const double factor = std::min(k, 4) / 4.0;
      const Wrench out = rig.cycle(push);
      EXPECT_NEAR(out.force.x(), 4.0 * factor, 1e-12);
      EXPECT_NEAR(out.torque.z(), 0.8 * factor, 1e-12);
      EXPECT_EQ(rig.safe.last_write_events() == safety_ramping, k < 4);
    }
  }
}

TEST(SafeDevice, MapsPosesVelocitiesAndWrenchesBetweenWorkspaces) {
  WorkspaceMapping mapping;
  mapping.scale = 2.0;
  mapping.offset.position = Eigen::Vector3d(1, 0, 0);
  mapping.offset.orientation = Eigen::AngleAxisd(std::numbers::pi / 2, Eigen::Vector3d::UnitZ());
  mapping.force_scale = 0.5;
  Rig rig({}, mapping);
  const Eigen::Quaterniond device_orientation(Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitX()));
  rig.device.set_pose(Pose{Eigen::Vector3d(0.1, 0, 0.05), device_orientation});
  const Wrench out = rig.cycle(wrench({0, 4, 0}, {0, 0, 0.5}));
  // x_virtual = t + R s x_device: (0.1, 0, 0.05) → scaled (0.2, 0, 0.1) → rotated (0, 0.2, 0.1).
  EXPECT_LT((rig.state.pose.position - Eigen::Vector3d(1, 0.2, 0.1)).norm(), 1e-12);
  EXPECT_LT(
      rig.state.pose.orientation.angularDistance(mapping.offset.orientation * device_orientation),
      1e-12);
  // F_device = β Rᵀ F_virtual: (0, 4, 0) → (4, 0, 0) → halved.
  EXPECT_LT((out.force - Eigen::Vector3d(2, 0, 0)).norm(), 1e-12);
  EXPECT_LT((out.torque - Eigen::Vector3d(0, 0, 0.5)).norm(), 1e-12);

  // Changing the scale keeps the virtual position; device motion then moves it by the new scale.
  rig.safe.set_scale(4.0);
  rig.cycle();
  EXPECT_LT((rig.state.pose.position - Eigen::Vector3d(1, 0.2, 0.1)).norm(), 1e-12);
  rig.device.set_pose(Pose{Eigen::Vector3d(0.11, 0, 0.05), device_orientation});
  rig.cycle();
  EXPECT_LT((rig.state.pose.position - Eigen::Vector3d(1, 0.24, 0.1)).norm(), 1e-12);
}

TEST(SafeDevice, IndexingHoldsTheVirtualPoseAndReleasesWithoutAJump) {
  Rig rig({.index_button = 1});
  const Pose start{Eigen::Vector3d(0.05, 0, 0), Eigen::Quaterniond::Identity()};
  rig.device.set_pose(start);
  rig.cycle();
  const Pose virtual_start = rig.state.pose;

  // Hold the button and carry the device back to the centre, turning it.
  rig.device.set_buttons(0b10);
  for (int i = 1; i <= 10; ++i) {
    const Pose moved{start.position * (1.0 - i / 10.0),
                     Eigen::Quaterniond(Eigen::AngleAxisd(0.05 * i, Eigen::Vector3d::UnitY()))};
    rig.device.set_pose(moved);
    const Wrench out = rig.cycle(wrench({1, 0, 0}));
    EXPECT_TRUE(rig.safe.indexing());
    EXPECT_EQ(out.force, Eigen::Vector3d::Zero());
    EXPECT_EQ(rig.state.pose.position, virtual_start.position);
    EXPECT_LT(rig.state.pose.orientation.angularDistance(virtual_start.orientation), 1e-12);
  }
  EXPECT_EQ(rig.safe.statistics().indexed_cycles, 10u);
  EXPECT_EQ(rig.safe.statistics().zeroed_writes, 0u);  // indexing is not a fault

  // Release: no jump, and motion continues from there in the device's new orientation.
  rig.device.set_buttons(0);
  const Wrench out = rig.cycle(wrench({1, 0, 0}));
  EXPECT_FALSE(rig.safe.indexing());
  EXPECT_LT((rig.state.pose.position - virtual_start.position).norm(), 1e-12);
  EXPECT_LT(rig.state.pose.orientation.angularDistance(virtual_start.orientation), 1e-12);
  EXPECT_GT(out.force.norm(), 0.0);
  const Eigen::Quaterniond held(Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitY()));
  rig.device.set_pose(Pose{Eigen::Vector3d(0.01, 0, 0), held});
  rig.cycle();
  // The device's +x is now the virtual world's R x with R = q_virtual q_device⁻¹.
  const Eigen::Vector3d expected =
      virtual_start.position + held.conjugate() * Eigen::Vector3d(0.01, 0, 0);
  EXPECT_LT((rig.state.pose.position - expected).norm(), 1e-12);
}

TEST(SafeDevice, RejectsInvalidSettingsAndCapabilities) {
  NullDevice device;
  EXPECT_TRUE(test::throws_with_message<Error>(
      [&] { SafeDevice safe(device, {.deadline_tolerance = -1.0}); }, "deadline_tolerance"));
  EXPECT_TRUE(test::throws_with_message<Error>(
      [&] { SafeDevice safe(device, {.index_button = 32}); }, "index_button"));
  WorkspaceMapping mapping;
  mapping.scale = 0.0;
  EXPECT_TRUE(
      test::throws_with_message<Error>([&] { SafeDevice safe(device, {}, mapping); }, "scale"));
  DeviceCapabilities capabilities = NullDevice::default_capabilities();
  capabilities.output_dof = 2;
  NullDevice odd(capabilities);
  SafeDevice safe(odd);
  EXPECT_TRUE(test::throws_with_message<Error>([&] { safe.open(); }, "output_dof"));
  EXPECT_FALSE(odd.is_open());
}

// The verification item: a device that returns NaN or disconnects in the middle of a contact
// gets zero within the cycle and its output back afterwards (through the ramp).
TEST(SafeDevice, FaultsMidContactZeroTheWrenchWithinOneCycleAndRecover) {
  // The hand pushes the simulated device 2 cm into a wall at x = 0 rendered at 1500 N/m.
  double depth = 0.02;  // where the hand pushes (m)
  SimulatedOperatorOptions options;
  options.start_at_target = false;
  SimulatedOperator device(
      [&](double) {
        return Pose{Eigen::Vector3d(depth, 0, 0), Eigen::Quaterniond::Identity()};
      },
      options);
  SafeDevice safe(device, {.ramp_cycles = 5});
  safe.open();
  DeviceState state;
  const auto wall = [&] {
    return wrench({state.valid ? -1500.0 * std::max(0.0, state.pose.position.x()) : nan, 0, 0});
  };
  const auto cycle = [&] {
    safe.read(state);
    safe.write(wall());
    return device.applied_wrench().force.x();
  };
  for (int i = 0; i < 1000; ++i) cycle();
  const double contact = cycle();
  EXPECT_LT(contact, -1.0);  // in contact, pushing back

  for (const bool disconnect : {false, true}) {
    SCOPED_TRACE(disconnect ? "disconnect" : "NaN pose");
    depth = 0.02;
    for (int i = 0; i < 1000; ++i) cycle();
    if (disconnect) {
      device.inject_disconnect(3);
    } else {
      device.inject_invalid_pose(3);
    }
    for (int i = 0; i < 3; ++i) {
      EXPECT_EQ(cycle(), 0.0);  // the very cycle of the fault renders nothing
      EXPECT_FALSE(state.valid);
    }
    // Back, still pressed 2 cm in (30 N): nothing until the hand eases off to 1 N or less.
    for (int i = 0; i < 50; ++i) EXPECT_EQ(cycle(), 0.0);
    EXPECT_TRUE(state.valid);
    EXPECT_EQ(safe.last_write_events(), safety_waiting_for_small_force);
    depth = 0.0005;  // 0.75 N
    double resumed = 0.0;
    for (int i = 0;; ++i) {
      ASSERT_LT(i, 5000) << "the hand eased off but output never resumed";
      resumed = cycle();
      if ((safe.last_write_events() & safety_waiting_for_small_force) == 0) break;
      EXPECT_EQ(resumed, 0.0);
    }
    // That cycle began the ramp, which brings the contact force back in five cycles, no jolt.
    EXPECT_NEAR(resumed, wall().force.x() / 5.0, 1e-9);
    EXPECT_GE(wall().force.x(), -1.0);
    for (int k = 2; k <= 5; ++k) {
      const double force = cycle();
      EXPECT_NEAR(force, wall().force.x() * k / 5.0, 1e-9);
    }
  }

  EXPECT_EQ(safe.statistics().read_failures, 3u);
  EXPECT_EQ(safe.statistics().invalid_inputs, 3u);
  EXPECT_EQ(device.rejected_writes(), 0u);  // nothing non-finite ever reached the device
}

TEST(SafeDevice, ReadAndWriteDoNotAllocate) {
  Rig rig({.ramp_cycles = 3, .passivity_control = true, .index_button = 0},
          {.scale = 2.0, .offset = {}, .force_scale = 1.0, .torque_scale = 1.0});
  test::allocation_count = 0;
  for (int i = 0; i < 100; ++i) {
    rig.device.set_buttons(i % 10 < 3 ? 1u : 0u);
    // Moving along the force pushing it: the passivity controller sees energy given and damps.
    Pose moving;
    moving.position.x() = 1e-3 * i;
    rig.device.set_pose(moving);
    rig.safe.begin_cycle(0.001 * i);
    rig.cycle(wrench({i % 7 == 0 ? nan : 20.0, 1, 0}, {0, 2, 0}));
    rig.safe.end_cycle(0.001 * i + (i % 13 == 0 ? 1.0 : 0.0));
  }
  EXPECT_EQ(test::allocation_count.load(), 0u);
  EXPECT_GT(rig.safe.statistics().deadline_misses, 0u);
  EXPECT_GT(rig.safe.statistics().clamped_writes, 0u);
  EXPECT_GT(rig.safe.statistics().passivity_damped_writes, 0u);
}

}  // namespace
}  // namespace khz::haptic
