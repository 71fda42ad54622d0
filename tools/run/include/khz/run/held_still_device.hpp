#pragma once
// A device that stops moving: for a steady press (issue 19's settling target), any scene's device
// replayed until a moment and then held there at rest.

#include <khz/haptic/device/device.hpp>

#include <memory>

namespace khz::run {

/// Wraps a device (owned) and, from the first reading at or after `hold_time` (s, the device's
/// clock), reports the pose of that reading at rest: zero velocities, the clock and buttons as
/// the device gives them. Everything else is the wrapped device's. Faults pass through (a failed
/// read still fails).
class HeldStillDevice final : public haptic::Device {
 public:
  HeldStillDevice(std::unique_ptr<haptic::Device> device, double hold_time);

  void open() override;
  void close() noexcept override { m_device->close(); }
  bool is_open() const noexcept override { return m_device->is_open(); }
  const haptic::DeviceCapabilities& capabilities() const noexcept override {
    return m_device->capabilities();
  }
  bool read(haptic::DeviceState& state) noexcept override;
  bool write(const haptic::Wrench& wrench) noexcept override { return m_device->write(wrench); }

 private:
  std::unique_ptr<haptic::Device> m_device;
  double m_hold_time;
  bool m_held = false;
  haptic::Pose m_pose;
};

}  // namespace khz::run
