// A Kilohertz device backed by CHAI3D's device layer (cGenericHapticDevice): any device CHAI3D
// supports. Built only when CHAI3D is found (examples/CMakeLists.txt); see docs/DEVICES.md.
// CHAI3D leaves the servo loop to the application; its units are SI already.

#include "spring_loop.hpp"

#include <khz/haptic/device/device.hpp>

#include <chai3d.h>

#include <chrono>

namespace {

using namespace khz::haptic;

Eigen::Vector3d to_eigen(const chai3d::cVector3d& v) { return {v.x(), v.y(), v.z()}; }

class Chai3dDevice final : public Device {
 public:
  ~Chai3dDevice() override { close(); }

  void open() override {
    if (!m_handler.getDevice(m_device, 0) || !m_device->open()) {
      throw IoError("CHAI3D: no haptic device");
    }
    m_device->calibrate();
    const chai3d::cHapticDeviceInfo info = m_device->getSpecifications();
    m_capabilities.name = info.m_modelName;
    m_capabilities.input_dof = info.m_sensedRotation ? 6 : 3;
    m_capabilities.output_dof = info.m_actuatedRotation ? 6 : 3;
    m_capabilities.max_force = info.m_maxLinearForce;
    m_capabilities.max_torque = info.m_maxAngularTorque;
    m_capabilities.max_stiffness = info.m_maxLinearStiffness;
    m_capabilities.workspace_radius = info.m_workspaceRadius;
    m_capabilities.workspace_max = Eigen::Vector3d::Constant(info.m_workspaceRadius);
    m_capabilities.workspace_min = -m_capabilities.workspace_max;
    m_start = std::chrono::steady_clock::now();
    m_open = true;
  }

  void close() noexcept override {
    if (!m_open) return;
    m_device->setForceAndTorque(chai3d::cVector3d(0, 0, 0), chai3d::cVector3d(0, 0, 0));
    m_device->close();
    m_open = false;
  }

  bool is_open() const noexcept override { return m_open; }
  const DeviceCapabilities& capabilities() const noexcept override { return m_capabilities; }

  bool read(DeviceState& state) noexcept override {
    chai3d::cVector3d position, velocity, angular_velocity;
    chai3d::cMatrix3d rotation;
    unsigned int switches = 0;
    state.valid = m_device->getPosition(position) && m_device->getRotation(rotation) &&
                  m_device->getLinearVelocity(velocity) &&
                  m_device->getAngularVelocity(angular_velocity) &&
                  m_device->getUserSwitches(switches);
    if (!state.valid) return false;
    Eigen::Matrix3d r;
    r << to_eigen(rotation.getCol0()), to_eigen(rotation.getCol1()), to_eigen(rotation.getCol2());
    state.pose.position = to_eigen(position);
    state.pose.orientation = Eigen::Quaterniond(r);
    state.linear_velocity = to_eigen(velocity);
    state.angular_velocity = to_eigen(angular_velocity);
    state.has_linear_velocity = true;
    state.has_angular_velocity = m_capabilities.input_dof == 6;
    state.buttons = switches;
    state.time = std::chrono::duration<double>(std::chrono::steady_clock::now() - m_start).count();
    return true;
  }

  bool write(const Wrench& w) noexcept override {
    const Eigen::Vector3d& f = w.force;
    const Eigen::Vector3d& t = w.torque;
    return m_device->setForceAndTorque(chai3d::cVector3d(f.x(), f.y(), f.z()),
                                       chai3d::cVector3d(t.x(), t.y(), t.z()));
  }

 private:
  chai3d::cHapticDeviceHandler m_handler;
  chai3d::cGenericHapticDevicePtr m_device;
  DeviceCapabilities m_capabilities;
  bool m_open = false;
  std::chrono::steady_clock::time_point m_start;
};

}  // namespace

int main() {
  Chai3dDevice device;
  return khz::example::run_spring(device);
}
