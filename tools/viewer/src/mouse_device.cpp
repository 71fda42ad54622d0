#include <khz/viewer/mouse_device.hpp>

namespace khz::viewer {

MouseDevice::MouseDevice(double nominal_rate, double reach) {
  m_capabilities.name = "mouse";
  m_capabilities.input_dof = 3;
  m_capabilities.output_dof = 0;
  m_capabilities.max_force = 10.0;
  m_capabilities.max_stiffness = 2000.0;
  m_capabilities.workspace_min = Eigen::Vector3d::Constant(-reach);
  m_capabilities.workspace_max = Eigen::Vector3d::Constant(reach);
  m_capabilities.nominal_rate = nominal_rate;
  m_capabilities.validate();
}

void MouseDevice::open() {
  m_opened = std::chrono::steady_clock::now();
  m_open = true;
}

bool MouseDevice::read(haptic::DeviceState& state) noexcept {
  if (!m_open) {
    state.valid = false;
    return false;
  }
  m_position.update();
  state.pose.position = m_position.front();
  state.pose.orientation.setIdentity();
  state.linear_velocity.setZero();
  state.angular_velocity.setZero();
  state.has_linear_velocity = false;
  state.has_angular_velocity = false;
  state.buttons = 0;
  state.time = std::chrono::duration<double>(std::chrono::steady_clock::now() - m_opened).count();
  state.valid = true;
  return true;
}

bool MouseDevice::write(const haptic::Wrench& wrench) noexcept {
  if (!m_open) return false;
  m_wrench.back() = wrench;
  m_wrench.publish();
  return true;
}

void MouseDevice::set_position(const Eigen::Vector3d& position) noexcept {
  if (!position.allFinite()) return;
  m_position.back() =
      position.cwiseMax(m_capabilities.workspace_min).cwiseMin(m_capabilities.workspace_max);
  m_position.publish();
}

const haptic::Wrench& MouseDevice::last_wrench() noexcept {
  m_wrench.update();
  return m_wrench.front();
}

}  // namespace khz::viewer
