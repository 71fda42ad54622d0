#pragma once
// A device that replays a recorded manipulandum trajectory and records what was rendered:
// reproducible runs of the whole haptic pipeline without hardware (thesis §3.13, §4.5).

#include <khz/haptic/common.hpp>
#include <khz/haptic/device/device.hpp>
#include <khz/haptic/device/trajectory_file.hpp>
#include <khz/haptic/export.hpp>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <span>
#include <vector>

namespace khz::haptic {

/// How a TrajectoryDevice advances.
enum class Playback {
  /// Each read() returns the next sample, whatever the sample times: the run is the same
  /// sequence of poses at any loop rate. state.time is the sample's time.
  sample_per_read,
  /// Each read() advances the clock by 1 / nominal_rate from the first sample's time and
  /// interpolates the pose (linear position, slerp orientation; buttons of the sample at or
  /// before the time). Replays a trajectory recorded at another rate in real time.
  at_nominal_rate,
};

struct TrajectoryDeviceOptions {
  Playback playback = Playback::sample_per_read;
  /// Wrenches the record can hold (allocated by open(), never in write()); writes beyond it are
  /// counted in dropped_records(). 0: one pass, i.e. the number of reads until finished(), + 1.
  std::size_t record_capacity = 0;
};

/// Replays samples through read() and keeps every written wrench with the time of the cycle's
/// read. After the last sample it keeps returning the last one and finished() is true.
/// Velocities are the difference quotients of the current segment (zero before the second
/// sample). open() rewinds and clears the record.
class KHZ_HAPTIC_API TrajectoryDevice final : public Device {
 public:
  /// NullDevice::default_capabilities() named "trajectory".
  static DeviceCapabilities default_capabilities();

  /// @throws Error if `samples` is empty or its times do not strictly increase.
  explicit TrajectoryDevice(std::vector<TrajectorySample> samples,
                            const TrajectoryDeviceOptions& options = {},
                            DeviceCapabilities capabilities = default_capabilities());
  /// Reads the samples with read_trajectory(). @throws IoError, ParseError.
  explicit TrajectoryDevice(const std::filesystem::path& file,
                            const TrajectoryDeviceOptions& options = {},
                            DeviceCapabilities capabilities = default_capabilities());

  void open() override;
  void close() noexcept override { m_open = false; }
  bool is_open() const noexcept override { return m_open; }
  const DeviceCapabilities& capabilities() const noexcept override { return m_capabilities; }
  bool read(DeviceState& state) noexcept override;
  bool write(const Wrench& wrench) noexcept override;

  /// True once read() has returned the last sample (or reached the last sample's time).
  bool finished() const noexcept { return m_finished; }
  /// Starts the replay again from the first sample (the record is kept).
  void rewind() noexcept;

  const std::vector<TrajectorySample>& samples() const noexcept { return m_samples; }
  std::span<const RecordedWrench> recorded() const noexcept { return m_record; }
  std::uint64_t dropped_records() const noexcept { return m_dropped; }
  /// Writes recorded() as CSV (format_wrench_record()). @throws IoError.
  void write_record(const std::filesystem::path& file) const;

 private:
  std::vector<TrajectorySample> m_samples;
  TrajectoryDeviceOptions m_options;
  DeviceCapabilities m_capabilities;
  bool m_open = false;
  std::uint64_t m_reads = 0;  // reads since the start of the replay
  std::size_t m_segment = 0;  // at_nominal_rate: index of the sample at or before the clock
  bool m_finished = false;
  double m_time = 0.0;  // time of the last read
  std::vector<RecordedWrench> m_record;
  std::uint64_t m_dropped = 0;
};

}  // namespace khz::haptic
