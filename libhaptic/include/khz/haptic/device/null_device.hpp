#pragma once
// A device that is not there: a settable fixed pose in, writes kept for inspection and otherwise
// discarded. For tests, benchmarks and running the loop without hardware.

#include <khz/haptic/common.hpp>
#include <khz/haptic/device/device.hpp>
#include <khz/haptic/export.hpp>

#include <cstdint>

namespace khz::haptic {

class KHZ_HAPTIC_API NullDevice final : public Device {
 public:
  /// 6-DOF in and out, 10 N, 1 N·m, 2000 N/m, a 0.2 m cube around the origin, 1 kHz.
  static DeviceCapabilities default_capabilities();

  explicit NullDevice(DeviceCapabilities capabilities = default_capabilities());

  void open() override { m_open = true; }
  void close() noexcept override { m_open = false; }
  bool is_open() const noexcept override { return m_open; }
  const DeviceCapabilities& capabilities() const noexcept override { return m_capabilities; }

  /// The set pose and buttons, zero velocities, time = reads so far / nominal rate. False while
  /// closed.
  bool read(DeviceState& state) noexcept override;
  /// Keeps the wrench (see last_written()). False while closed.
  bool write(const Wrench& wrench) noexcept override;

  /// What read() reports from now on (call from the haptic thread or while no loop runs).
  void set_pose(const Pose& pose) noexcept { m_pose = pose; }
  void set_buttons(std::uint32_t buttons) noexcept { m_buttons = buttons; }

  const Wrench& last_written() const noexcept { return m_last; }
  std::uint64_t read_count() const noexcept { return m_reads; }
  std::uint64_t write_count() const noexcept { return m_writes; }

 private:
  DeviceCapabilities m_capabilities;
  bool m_open = false;
  Pose m_pose;
  std::uint32_t m_buttons = 0;
  Wrench m_last;
  std::uint64_t m_reads = 0;
  std::uint64_t m_writes = 0;
};

}  // namespace khz::haptic
