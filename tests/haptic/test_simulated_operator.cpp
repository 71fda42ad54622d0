// The simulated operator: a virtual device + hand that closes the haptic loop without hardware.

#include <khz/haptic/device/simulated_operator.hpp>
#include <khz/test/allocation_probe.hpp>
#include <khz/test/fixtures.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace khz::haptic {
namespace {

/// Step response of m ẍ + b ẋ + k x = k A from rest at 0 (underdamped).
double step_response(double m, double b, double k, double amplitude, double t) {
  const double omega = std::sqrt(k / m);
  const double zeta = b / (2.0 * std::sqrt(k * m));
  const double omega_d = omega * std::sqrt(1.0 - zeta * zeta);
  return amplitude *
         (1.0 - std::exp(-zeta * omega * t) *
                    (std::cos(omega_d * t) + zeta * omega / omega_d * std::sin(omega_d * t)));
}

struct StepErrors {
  double position = 0.0;  // m, largest deviation from the analytic step response
  double angle = 0.0;     // rad
};

/// Runs a step of the target (1 cm along x, 0.2 rad about z) with nothing rendered and compares
/// with the analytic damped oscillators.
StepErrors step_errors(int substeps) {
  SimulatedOperatorOptions options;
  options.start_at_target = false;
  options.substeps = substeps;
  const Pose target{Eigen::Vector3d(0.01, 0, 0),
                    Eigen::Quaterniond(Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitZ()))};
  SimulatedOperator device([&](double) { return target; }, options);
  device.open();
  const double m = options.device.mass + options.hand.mass;
  const double b = options.device.damping + options.hand.damping;
  const double inertia = options.device.inertia + options.hand.inertia;
  const double b_rot = options.device.rotational_damping + options.hand.rotational_damping;
  StepErrors errors;
  DeviceState state;
  for (int i = 0; i < 1000; ++i) {
    EXPECT_TRUE(device.read(state));
    EXPECT_NEAR(state.time, 0.001 * i, 1e-12);
    const double x = step_response(m, b, options.hand.stiffness, 0.01, state.time);
    const double angle =
        step_response(inertia, b_rot, options.hand.rotational_stiffness, 0.2, state.time);
    const Eigen::AngleAxisd rotation(state.pose.orientation);
    errors.position =
        std::max(errors.position, (state.pose.position - Eigen::Vector3d(x, 0, 0)).norm());
    errors.angle =
        std::max(errors.angle,
                 (rotation.angle() * rotation.axis() - angle * Eigen::Vector3d::UnitZ()).norm());
    device.write(Wrench{});
  }
  return errors;
}

TEST(SimulatedOperator, FollowsAStepLikeTheDampedOscillator) {
  const StepErrors coarse = step_errors(1);
  const StepErrors fine = step_errors(4);
  const StepErrors standard = step_errors(10);
  // First order: four times smaller steps, about four times smaller errors.
  EXPECT_GT(coarse.position / fine.position, 3.5);
  EXPECT_GT(coarse.angle / fine.angle, 3.5);
  // At the default 10 substeps per 1 ms period: within 0.5 % of the step.
  EXPECT_LT(standard.position, 0.005 * 0.01);
  EXPECT_LT(standard.angle, 0.005 * 0.2);
}

TEST(SimulatedOperator, TracksKeyframesAndSettlesAtTheTarget) {
  const Pose start;
  const Pose end{Eigen::Vector3d(0.05, -0.02, 0.01),
                 Eigen::Quaterniond(Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitX()))};
  const TargetFunction target = keyframe_target({{0.1, start}, {0.6, end}});
  EXPECT_EQ(target(0.0).position, start.position);
  EXPECT_LT((target(0.35).position - 0.5 * end.position).norm(), 1e-15);
  EXPECT_NEAR(Eigen::AngleAxisd(target(0.35).orientation).angle(), 0.2, 1e-12);
  EXPECT_EQ(target(9.0).position, end.position);

  SimulatedOperator device(target);
  device.open();
  DeviceState state;
  double largest_lag = 0.0;
  for (int i = 0; i < 2000; ++i) {
    device.read(state);
    largest_lag = std::max(largest_lag, (state.pose.position - target(state.time).position).norm());
  }
  EXPECT_GT(largest_lag, 1e-3);  // it lags while the target moves at 11 cm/s...
  EXPECT_LT((state.pose.position - end.position).norm(), 1e-6);  // ...and settles
  EXPECT_LT(state.pose.orientation.angularDistance(end.orientation), 1e-6);
  EXPECT_LT(state.linear_velocity.norm(), 1e-4);
  EXPECT_LT(device.kinetic_energy() + device.hand_energy(), 1e-10);
}

// A scripted operator's button presses: held from their keyframe until the next, none before
// the first; read() reports them at the device's time, and allocates nothing doing so.
TEST(SimulatedOperator, ReportsTheButtonsItsKeyframesHold) {
  const std::vector<Keyframe> frames{
      {0.1, Pose{}, 0u}, {0.2, Pose{}, 1u}, {0.3, Pose{}, 5u}, {0.4, Pose{}, 0u}};
  const ButtonFunction buttons = keyframe_buttons(frames);
  ASSERT_TRUE(static_cast<bool>(buttons));
  EXPECT_EQ(buttons(0.0), 0u);
  EXPECT_EQ(buttons(0.15), 0u);
  EXPECT_EQ(buttons(0.2), 1u);
  EXPECT_EQ(buttons(0.25), 1u);
  EXPECT_EQ(buttons(0.35), 5u);
  EXPECT_EQ(buttons(9.0), 0u);
  EXPECT_FALSE(static_cast<bool>(keyframe_buttons({{0.0, Pose{}}, {1.0, Pose{}}})))
      << "no presses: no function to call per read";

  SimulatedOperator device(keyframe_target(frames), {}, buttons);
  device.open();
  DeviceState state;
  std::vector<std::uint32_t> read;
  read.reserve(10);
  test::allocation_count = 0;
  for (int i = 0; i < 500; ++i) {
    device.read(state);
    if (i % 50 == 25) read.push_back(state.buttons);  // at 25, 75, ... ms
  }
  EXPECT_EQ(test::allocation_count.load(), 0u);
  EXPECT_EQ(read, (std::vector<std::uint32_t>{0, 0, 0, 0, 1, 1, 5, 5, 0, 0}));
}

/// The hand pushes the device through x = 0 towards a target 2 cm behind a wall rendered as
/// F = −k max(0, x) through write(), sampled at 1 kHz. Returns the positions, one per read.
std::vector<double> push_into_wall(double wall_stiffness, double damping, const Pose& start,
                                   const TargetFunction& target, double seconds) {
  SimulatedOperatorOptions options;
  options.hand.damping = damping;
  options.device.damping = 0.0;
  options.start_at_target = false;
  options.initial_pose = start;
  SimulatedOperator device(target, options);
  device.open();
  std::vector<double> positions;
  DeviceState state;
  for (int i = 0; i < int(seconds * 1000); ++i) {
    device.read(state);
    positions.push_back(state.pose.position.x());
    Wrench wall;
    wall.force.x() = -wall_stiffness * std::max(0.0, positions.back());
    device.write(wall);
  }
  return positions;
}

/// Largest |x − centre| over reads [first, last).
double amplitude(const std::vector<double>& x, double centre, int first, int last) {
  double largest = 0.0;
  for (int i = first; i < last; ++i) largest = std::max(largest, std::abs(x[i] - centre));
  return largest;
}

TEST(SimulatedOperator, AStiffWallRenderedThroughWriteStopsTheDevice) {
  // 3000 N/m with 6 N·s/m of hand damping (b > k T / 2 = 1.5 N·s/m): passive. The target moves
  // from 3 cm outside to 2 cm behind the wall in 0.5 s.
  const Pose outside{Eigen::Vector3d(-0.03, 0, 0), Eigen::Quaterniond::Identity()};
  const Pose behind{Eigen::Vector3d(0.02, 0, 0), Eigen::Quaterniond::Identity()};
  const std::vector<double> x =
      push_into_wall(3000.0, 6.0, outside, keyframe_target({{0.0, outside}, {0.5, behind}}), 3.0);
  const double equilibrium = 300.0 * 0.02 / 3300.0;  // hand and wall springs in balance
  EXPECT_NEAR(x.back(), equilibrium, 1e-6);
  EXPECT_LT(*std::max_element(x.begin(), x.end()), 1.5 * equilibrium);  // no deep overshoot
  EXPECT_LT(amplitude(x, equilibrium, 2500, 3000), 1e-6);               // at rest
}

TEST(SimulatedOperator, WallStabilityFollowsColgatesCondition) {
  // In contact at 0.1 mm from equilibrium: the sampled, held wall acts like a spring plus a
  // negative damping of k T / 2 = 1.5 N·s/m. With less physical damping than that the contact
  // oscillation grows, with more it dies out. The simulated operator must show both, or it could
  // not be used to test stability.
  const Pose behind{Eigen::Vector3d(0.02, 0, 0), Eigen::Quaterniond::Identity()};
  const double equilibrium = 300.0 * 0.02 / 3300.0;
  const Pose start{Eigen::Vector3d(equilibrium + 1e-4, 0, 0), Eigen::Quaterniond::Identity()};
  const auto target = [&](double) { return behind; };
  const std::vector<double> active = push_into_wall(3000.0, 0.5, start, target, 2.0);
  const std::vector<double> passive = push_into_wall(3000.0, 2.5, start, target, 2.0);
  const double active_growth =
      amplitude(active, equilibrium, 1500, 2000) / amplitude(active, equilibrium, 0, 500);
  const double passive_growth =
      amplitude(passive, equilibrium, 1500, 2000) / amplitude(passive, equilibrium, 0, 500);
  EXPECT_GT(active_growth, 2.0) << passive_growth;
  EXPECT_LT(passive_growth, 0.5) << active_growth;
}

TEST(SimulatedOperator, SaturatesWritesAndInjectsFaults) {
  SimulatedOperator device([](double) { return Pose{}; });
  EXPECT_FALSE(device.write(Wrench{}));  // closed
  device.open();
  DeviceState state;
  ASSERT_TRUE(device.read(state));
  Wrench strong;
  strong.force = Eigen::Vector3d(0, 30, 40);
  strong.torque = Eigen::Vector3d(5, 0, 0);
  EXPECT_TRUE(device.write(strong));
  EXPECT_LT((device.applied_wrench().force - Eigen::Vector3d(0, 5.1, 6.8)).norm(), 1e-12);
  EXPECT_LT((device.applied_wrench().torque - Eigen::Vector3d(0.5, 0, 0)).norm(), 1e-12);

  Wrench broken;
  broken.torque.y() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(device.write(broken));
  EXPECT_EQ(device.rejected_writes(), 1u);
  EXPECT_EQ(device.applied_wrench().force, Eigen::Vector3d::Zero());

  device.write(strong);
  device.inject_disconnect(2);
  EXPECT_EQ(device.applied_wrench().force, Eigen::Vector3d::Zero());  // amplifiers off
  for (int i = 0; i < 2; ++i) {
    EXPECT_FALSE(device.read(state));
    EXPECT_FALSE(state.valid);
    EXPECT_FALSE(device.write(strong));
  }
  const double time = device.time();
  EXPECT_NEAR(time, 0.002, 1e-12);  // the simulation kept running
  EXPECT_TRUE(device.read(state));
  EXPECT_TRUE(device.write(strong));

  device.inject_invalid_pose(1);
  EXPECT_TRUE(device.read(state));
  EXPECT_TRUE(state.valid);
  EXPECT_TRUE(std::isnan(state.pose.position.x()));
  EXPECT_TRUE(device.read(state));
  EXPECT_FALSE(std::isnan(state.pose.position.x()));
}

TEST(SimulatedOperator, ThreeDofDevicesReportNoOrientationAndRenderNoTorque) {
  SimulatedOperatorOptions options;
  options.capabilities.input_dof = 3;
  options.capabilities.output_dof = 3;
  const Pose turned{Eigen::Vector3d::Zero(),
                    Eigen::Quaterniond(Eigen::AngleAxisd(1.0, Eigen::Vector3d::UnitY()))};
  SimulatedOperator device([&](double) { return turned; }, options);
  device.open();
  DeviceState state;
  device.read(state);
  EXPECT_EQ(state.pose.orientation.coeffs(), Eigen::Quaterniond::Identity().coeffs());
  EXPECT_FALSE(state.has_angular_velocity);
  Wrench w;
  w.torque.x() = 0.1;
  device.write(w);
  EXPECT_EQ(device.applied_wrench().torque, Eigen::Vector3d::Zero());
}

TEST(SimulatedOperator, RejectsUnstableOrInvalidSettings) {
  const auto target = [](double) { return Pose{}; };
  SimulatedOperatorOptions options;
  options.hand.stiffness = 1e9;  // h² k/m = 22 at 10 kHz integration: unstable
  EXPECT_TRUE(test::throws_with_message<Error>([&] { SimulatedOperator d(target, options); },
                                               "translation: h² k/m + 2 h b/m"));
  options = {};
  options.device.mass = 0.0;
  EXPECT_TRUE(
      test::throws_with_message<Error>([&] { SimulatedOperator d(target, options); }, "mass"));
  EXPECT_TRUE(test::throws_with_message<Error>([] { keyframe_target({}); }, "keyframe"));
  EXPECT_TRUE(test::throws_with_message<Error>(
      [] {
        keyframe_target({{1.0, Pose{}}, {1.0, Pose{}}});
      },
      "keyframe 1"));
}

TEST(SimulatedOperator, ReadAndWriteDoNotAllocate) {
  SimulatedOperator device(keyframe_target(
      {{0.0, Pose{}}, {0.05, Pose{Eigen::Vector3d(0.01, 0, 0), Eigen::Quaterniond::Identity()}}}));
  device.open();
  DeviceState state;
  Wrench w;
  test::allocation_count = 0;
  for (int i = 0; i < 100; ++i) {
    device.read(state);
    w.force.x() = -100.0 * state.pose.position.x();
    device.write(w);
  }
  EXPECT_EQ(test::allocation_count.load(), 0u);
}

}  // namespace
}  // namespace khz::haptic
