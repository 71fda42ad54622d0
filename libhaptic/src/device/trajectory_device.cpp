#include <khz/haptic/device/null_device.hpp>
#include <khz/haptic/device/trajectory_device.hpp>

#include <khz/haptic/coupling/rotation_vector.hpp>

#include "device/pose_math.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

namespace khz::haptic {
namespace {

void fill_segment_velocity(const TrajectorySample& a, const TrajectorySample& b,
                           DeviceState& state) noexcept {
  const double dt = b.time - a.time;
  state.linear_velocity = (b.pose.position - a.pose.position) / dt;
  state.angular_velocity =
      rotation_vector(b.pose.orientation * a.pose.orientation.conjugate()) / dt;
}

}  // namespace

DeviceCapabilities TrajectoryDevice::default_capabilities() {
  DeviceCapabilities capabilities = NullDevice::default_capabilities();
  capabilities.name = "trajectory";
  return capabilities;
}

TrajectoryDevice::TrajectoryDevice(std::vector<TrajectorySample> samples,
                                   const TrajectoryDeviceOptions& options,
                                   DeviceCapabilities capabilities)
    : m_samples(std::move(samples)), m_options(options), m_capabilities(std::move(capabilities)) {
  m_capabilities.validate();
  if (m_samples.empty()) throw Error("TrajectoryDevice: the trajectory has no samples");
  for (std::size_t i = 0; i < m_samples.size(); ++i) {
    TrajectorySample& sample = m_samples[i];
    if (!std::isfinite(sample.time) || (i > 0 && !(sample.time > m_samples[i - 1].time)) ||
        !detail::is_valid_pose(sample.pose)) {
      throw Error("TrajectoryDevice: sample " + std::to_string(i) +
                  " has a non-finite or non-increasing time or an invalid pose");
    }
    sample.pose.orientation.normalize();
  }
}

TrajectoryDevice::TrajectoryDevice(const std::filesystem::path& file,
                                   const TrajectoryDeviceOptions& options,
                                   DeviceCapabilities capabilities)
    : TrajectoryDevice(read_trajectory(file), options, std::move(capabilities)) {}

void TrajectoryDevice::open() {
  std::size_t capacity = m_options.record_capacity;
  if (capacity == 0) {
    const double duration = m_samples.back().time - m_samples.front().time;
    capacity =
        m_options.playback == Playback::sample_per_read
            ? m_samples.size() + 1
            : static_cast<std::size_t>(std::ceil(duration * m_capabilities.nominal_rate)) + 2;
  }
  m_record.clear();
  m_record.reserve(capacity);
  m_options.record_capacity = capacity;
  m_dropped = 0;
  rewind();
  m_open = true;
}

void TrajectoryDevice::rewind() noexcept {
  m_reads = 0;
  m_segment = 0;
  m_finished = false;
  m_time = m_samples.front().time;
}

bool TrajectoryDevice::read(DeviceState& state) noexcept {
  if (!m_open) {
    state.valid = false;
    return false;
  }
  const std::size_t last = m_samples.size() - 1;
  state.linear_velocity.setZero();
  state.angular_velocity.setZero();
  if (m_options.playback == Playback::sample_per_read) {
    const std::size_t i = static_cast<std::size_t>(std::min<std::uint64_t>(m_reads, last));
    const TrajectorySample& sample = m_samples[i];
    state.pose = sample.pose;
    state.buttons = sample.buttons;
    state.time = sample.time;
    if (i > 0 && m_reads <= last) fill_segment_velocity(m_samples[i - 1], sample, state);
    m_finished = i == last;
  } else {
    const double time = m_samples.front().time + double(m_reads) / m_capabilities.nominal_rate;
    while (m_segment < last && m_samples[m_segment + 1].time <= time) ++m_segment;
    const TrajectorySample& a = m_samples[m_segment];
    state.buttons = a.buttons;
    state.time = time;
    if (m_segment < last) {
      const TrajectorySample& b = m_samples[m_segment + 1];
      const double u = (time - a.time) / (b.time - a.time);
      state.pose.position = (1.0 - u) * a.pose.position + u * b.pose.position;
      state.pose.orientation = a.pose.orientation.slerp(u, b.pose.orientation);
      fill_segment_velocity(a, b, state);
    } else {
      state.pose = a.pose;
    }
    m_finished = m_segment == last;
  }
  state.has_linear_velocity = true;
  state.has_angular_velocity = m_capabilities.input_dof == 6;
  state.valid = true;
  m_time = state.time;
  ++m_reads;
  return true;
}

bool TrajectoryDevice::write(const Wrench& wrench) noexcept {
  if (!m_open) return false;
  if (m_record.size() < m_options.record_capacity) {
    m_record.push_back(RecordedWrench{m_time, wrench});
  } else {
    ++m_dropped;
  }
  return true;
}

void TrajectoryDevice::write_record(const std::filesystem::path& file) const {
  write_wrench_record(file, m_record);
}

}  // namespace khz::haptic
