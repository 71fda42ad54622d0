#include <khz/haptic/device/null_device.hpp>

#include <utility>

namespace khz::haptic {

DeviceCapabilities NullDevice::default_capabilities() {
  DeviceCapabilities capabilities;
  capabilities.name = "null device";
  capabilities.max_force = 10.0;
  capabilities.max_torque = 1.0;
  capabilities.max_stiffness = 2000.0;
  return capabilities;
}

NullDevice::NullDevice(DeviceCapabilities capabilities) : m_capabilities(std::move(capabilities)) {}

bool NullDevice::read(DeviceState& state) noexcept {
  if (!m_open) {
    state.valid = false;
    return false;
  }
  state.pose = m_pose;
  state.linear_velocity.setZero();
  state.angular_velocity.setZero();
  state.has_linear_velocity = true;
  state.has_angular_velocity = m_capabilities.input_dof == 6;
  state.buttons = m_buttons;
  state.time = double(m_reads) / m_capabilities.nominal_rate;
  state.valid = true;
  ++m_reads;
  return true;
}

bool NullDevice::write(const Wrench& wrench) noexcept {
  if (!m_open) return false;
  m_last = wrench;
  ++m_writes;
  return true;
}

}  // namespace khz::haptic
