// The trajectory file format and the device that replays it and records what was rendered.

#include <khz/haptic/device/trajectory_device.hpp>
#include <khz/haptic/device/trajectory_file.hpp>
#include <khz/test/allocation_probe.hpp>
#include <khz/test/fixtures.hpp>

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <numbers>
#include <vector>

namespace khz::haptic {
namespace {

/// A short trajectory with awkward numbers (no short decimal form) and buttons.
std::vector<TrajectorySample> wiggle(int count) {
  std::vector<TrajectorySample> samples;
  for (int i = 0; i < count; ++i) {
    TrajectorySample s;
    s.time = 0.001 * i + 1.0 / 3.0;
    s.pose.position = Eigen::Vector3d(std::sin(0.1 * i), 1e-7 * i, -std::numbers::pi * i / 7.0);
    s.pose.orientation =
        Eigen::Quaterniond(Eigen::AngleAxisd(0.05 * i, Eigen::Vector3d(1, 2, 3).normalized()));
    s.buttons = static_cast<std::uint32_t>(i % 3 == 0 ? 0u : 0x80000001u);
    samples.push_back(s);
  }
  return samples;
}

void expect_same_samples(const std::vector<TrajectorySample>& a,
                         const std::vector<TrajectorySample>& b, bool buttons) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    SCOPED_TRACE(i);
    EXPECT_EQ(a[i].time, b[i].time);
    EXPECT_EQ(a[i].pose.position, b[i].pose.position);
    // Parsing normalizes, which may move the last bit of an already unit quaternion.
    EXPECT_LT((a[i].pose.orientation.coeffs() - b[i].pose.orientation.coeffs()).norm(), 1e-15);
    EXPECT_EQ(buttons ? a[i].buttons : 0u, b[i].buttons);
  }
}

TEST(TrajectoryFile, TextRoundTripIsExact) {
  const std::vector<TrajectorySample> samples = wiggle(50);
  expect_same_samples(samples, parse_trajectory(format_trajectory(samples), "memory"), true);
  expect_same_samples(samples, parse_trajectory(format_trajectory(samples, false), "memory"),
                      false);
}

TEST(TrajectoryFile, FileRoundTrip) {
  const std::vector<TrajectorySample> samples = wiggle(20);
  const auto file = test::scratch_file("trajectory.csv");
  write_trajectory(file, samples);
  expect_same_samples(samples, read_trajectory(file), true);
  EXPECT_TRUE(test::throws_with_message<IoError>(
      [] { read_trajectory(test::scratch_file("missing.csv")); }, "missing.csv"));
}

TEST(TrajectoryFile, AcceptsPaddingCommentsCrlfAndByteOrderMark) {
  const std::string text =
      "\xEF\xBB\xBF# recorded by hand\r\n t , x,y,z,qw,qx,qy,qz,buttons\r\n\r\n"
      "0, 0.5 ,\t-1,2e-3,1,0,0,0, 3\r\n# pause\n0.25,0,0,0,0,1,0,0,0\n";
  const std::vector<TrajectorySample> samples = parse_trajectory(text, "padded.csv");
  ASSERT_EQ(samples.size(), 2u);
  EXPECT_EQ(samples[0].pose.position, Eigen::Vector3d(0.5, -1, 2e-3));
  EXPECT_EQ(samples[0].buttons, 3u);
  EXPECT_EQ(samples[1].time, 0.25);
  EXPECT_EQ(samples[1].pose.orientation.x(), 1.0);
}

TEST(TrajectoryFile, MalformedFilesAreRejectedWithTheirLine) {
  const std::array<test::MalformedFile, 10> cases = {{
      {"empty.csv", "empty.csv:1: file ends early: expected the header"},
      {"wrong_header.csv", "wrong_header.csv:1: expected the header 't,x,y,z,qw,qx,qy,qz"},
      {"no_samples.csv", "no_samples.csv:3: file ends early: expected at least one sample"},
      {"missing_field.csv", "missing_field.csv:3: expected 8 comma-separated fields, found 7"},
      {"non_numeric.csv", "non_numeric.csv:2: expected x (a finite number), found 'abc'"},
      {"nan_coordinate.csv", "nan_coordinate.csv:2: expected z (a finite number), found 'nan'"},
      {"time_not_increasing.csv", "time_not_increasing.csv:4: time 0 does not increase"},
      {"non_unit_quaternion.csv",
       "non_unit_quaternion.csv:2: the quaternion (qw,qx,qy,qz) has "
       "norm 2.000000"},
      {"buttons_out_of_range.csv", "buttons_out_of_range.csv:2: expected buttons"},
      {"negative_buttons.csv", "negative_buttons.csv:2: expected buttons (an integer bitmask"},
  }};
  test::expect_corpus_rejected("malformed/trajectory", cases,
                               [](const std::filesystem::path& file) { read_trajectory(file); });
}

TEST(TrajectoryDevice, ReplaysOneSamplePerReadAndHoldsTheLast) {
  const std::vector<TrajectorySample> samples = wiggle(5);
  TrajectoryDevice device(samples);
  DeviceState state;
  EXPECT_FALSE(device.read(state));  // closed
  EXPECT_FALSE(state.valid);
  device.open();
  for (std::size_t i = 0; i < samples.size() + 3; ++i) {
    SCOPED_TRACE(i);
    const std::size_t k = std::min(i, samples.size() - 1);
    ASSERT_TRUE(device.read(state));
    EXPECT_TRUE(state.valid);
    EXPECT_EQ(state.time, samples[k].time);
    EXPECT_EQ(state.pose.position, samples[k].pose.position);
    EXPECT_EQ(state.buttons, samples[k].buttons);
    EXPECT_EQ(device.finished(), k == samples.size() - 1);
    Eigen::Vector3d expected_velocity = Eigen::Vector3d::Zero();
    if (i > 0 && i < samples.size()) {
      expected_velocity = (samples[k].pose.position - samples[k - 1].pose.position) /
                          (samples[k].time - samples[k - 1].time);
    }
    EXPECT_LT((state.linear_velocity - expected_velocity).norm(), 1e-9);
  }
  // Angular velocity of a constant-rate rotation: 0.05 rad per sample about (1,2,3).
  device.rewind();
  device.read(state);
  device.read(state);
  EXPECT_LT((state.angular_velocity - 50.0 * Eigen::Vector3d(1, 2, 3).normalized()).norm(), 1e-9);
  EXPECT_FALSE(device.finished());
}

TEST(TrajectoryDevice, PlaysAtTheNominalRateByInterpolation) {
  std::vector<TrajectorySample> samples(2);
  samples[0].time = 1.0;
  samples[1].time = 1.01;  // 10 ms: ten reads at 1 kHz
  samples[1].pose.position = Eigen::Vector3d(0.01, 0, 0);
  samples[1].pose.orientation = Eigen::AngleAxisd(0.1, Eigen::Vector3d::UnitZ());
  samples[1].buttons = 1;
  TrajectoryDevice device(samples, {.playback = Playback::at_nominal_rate});
  device.open();
  DeviceState state;
  for (int i = 0; i <= 12; ++i) {
    SCOPED_TRACE(i);
    ASSERT_TRUE(device.read(state));
    const double u = std::min(i, 10) / 10.0;
    EXPECT_NEAR(state.time, 1.0 + 0.001 * i, 1e-12);
    EXPECT_NEAR(state.pose.position.x(), 0.01 * u, 1e-12);
    EXPECT_NEAR(Eigen::AngleAxisd(state.pose.orientation).angle(), 0.1 * u, 1e-9);
    EXPECT_EQ(state.buttons, i >= 10 ? 1u : 0u);
    EXPECT_EQ(device.finished(), i >= 10);
    EXPECT_NEAR(state.linear_velocity.x(), i < 10 ? 1.0 : 0.0, 1e-9);
  }
}

TEST(TrajectoryDevice, RecordsEveryWrittenWrenchWithItsTime) {
  const std::vector<TrajectorySample> samples = wiggle(3);
  TrajectoryDevice device(samples, {.record_capacity = 4});
  device.open();
  DeviceState state;
  for (int i = 0; i < 6; ++i) {
    device.read(state);
    Wrench w;
    w.force = Eigen::Vector3d(i, 0.5, -1.0 / 3.0);
    w.torque = Eigen::Vector3d(0, 0, 0.125 * i);
    EXPECT_TRUE(device.write(w));
  }
  ASSERT_EQ(device.recorded().size(), 4u);
  EXPECT_EQ(device.dropped_records(), 2u);
  EXPECT_EQ(device.recorded()[1].time, samples[1].time);
  EXPECT_EQ(device.recorded()[3].time, samples[2].time);  // held last sample
  EXPECT_EQ(device.recorded()[3].wrench.force.x(), 3.0);

  const auto file = test::scratch_file("record.csv");
  device.write_record(file);
  const std::string text = test::read_bytes(file);
  EXPECT_TRUE(
      text.starts_with("t,fx,fy,fz,tx,ty,tz\n0.3333333333333333,0,0.5,"
                       "-0.3333333333333333,0,0,0\n"))
      << text;
  EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), 5);

  device.open();  // rewinds and clears
  EXPECT_TRUE(device.recorded().empty());
  EXPECT_FALSE(device.finished());
}

TEST(TrajectoryDevice, ReadsAFileAndRejectsBadSamples) {
  const auto file = test::scratch_file("replay.csv");
  write_trajectory(file, wiggle(4));
  TrajectoryDevice device(file);
  EXPECT_EQ(device.samples().size(), 4u);
  EXPECT_TRUE(test::throws_with_message<Error>(
      [] { TrajectoryDevice empty(std::vector<TrajectorySample>{}); }, "no samples"));
  std::vector<TrajectorySample> backwards = wiggle(3);
  backwards[2].time = backwards[0].time;
  EXPECT_TRUE(
      test::throws_with_message<Error>([&] { TrajectoryDevice bad(backwards); }, "sample 2"));
}

TEST(TrajectoryDevice, ReadAndWriteDoNotAllocate) {
  for (const Playback playback : {Playback::sample_per_read, Playback::at_nominal_rate}) {
    TrajectoryDevice device(wiggle(100), {.playback = playback});
    device.open();
    DeviceState state;
    test::allocation_count = 0;
    for (int i = 0; i < 150; ++i) {
      device.read(state);
      device.write(Wrench{});
    }
    EXPECT_EQ(test::allocation_count.load(), 0u);
    EXPECT_EQ(device.recorded().size() + device.dropped_records(), 150u);
  }
}

}  // namespace
}  // namespace khz::haptic
