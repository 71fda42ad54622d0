#include <khz/run/held_still_device.hpp>

namespace khz::run {

HeldStillDevice::HeldStillDevice(std::unique_ptr<haptic::Device> device, double hold_time)
    : m_device(std::move(device)), m_hold_time(hold_time) {}

void HeldStillDevice::open() {
  m_device->open();
  m_held = false;
}

bool HeldStillDevice::read(haptic::DeviceState& state) noexcept {
  if (!m_device->read(state)) return false;
  if (!m_held && state.time >= m_hold_time) {
    m_pose = state.pose;
    m_held = true;
  }
  if (m_held) {
    state.pose = m_pose;
    state.linear_velocity.setZero();
    state.angular_velocity.setZero();
  }
  return true;
}

}  // namespace khz::run
