// A Kilohertz device backed by the Force Dimension SDK (DHD): omega.x, delta.x, sigma.x, Falcon.
// Built only when the SDK is found (examples/CMakeLists.txt); see docs/DEVICES.md. DHD is called
// from the application's own haptic thread; units are SI already.

#include "spring_loop.hpp"

#include <khz/haptic/device/device.hpp>

#include <dhdc.h>

#include <string>
#include <utility>

namespace {

using namespace khz::haptic;

class DhdDevice final : public Device {
 public:
  /// DHD reports the kinematics, not the limits: pass the data sheet's force, torque, stiffness
  /// and workspace; the DOF counts are read from the device.
  explicit DhdDevice(DeviceCapabilities limits) : m_capabilities(std::move(limits)) {}
  ~DhdDevice() override { close(); }

  void open() override {
    m_id = dhdOpen();
    if (m_id < 0) throw IoError(std::string("DHD: cannot open a device: ") + dhdErrorGetLastStr());
    m_capabilities.name = dhdGetSystemName(m_id);
    m_capabilities.input_dof = dhdHasWrist(m_id) ? 6 : 3;
    m_capabilities.output_dof = dhdHasActiveWrist(m_id) ? 6 : 3;
    dhdEnableForce(DHD_ON, m_id);
  }

  void close() noexcept override {
    if (m_id < 0) return;
    dhdSetForceAndTorque(0, 0, 0, 0, 0, 0, m_id);
    dhdClose(m_id);
    m_id = -1;
  }

  bool is_open() const noexcept override { return m_id >= 0; }
  const DeviceCapabilities& capabilities() const noexcept override { return m_capabilities; }

  bool read(DeviceState& state) noexcept override {
    double p[3], r[3][3], v[3];
    state.valid = dhdGetPositionAndOrientationFrame(&p[0], &p[1], &p[2], r, m_id) >= 0 &&
                  dhdGetLinearVelocity(&v[0], &v[1], &v[2], m_id) >= 0;
    if (!state.valid) return false;
    state.pose.position = Eigen::Vector3d(p[0], p[1], p[2]);
    state.pose.orientation = Eigen::Quaterniond(
        Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(&r[0][0]));
    state.linear_velocity = Eigen::Vector3d(v[0], v[1], v[2]);
    state.has_linear_velocity = true;
    state.buttons = static_cast<std::uint32_t>(dhdGetButtonMask(m_id));
    state.time = dhdGetTime();
    return true;
  }

  bool write(const Wrench& w) noexcept override {
    return dhdSetForceAndTorque(w.force.x(), w.force.y(), w.force.z(), w.torque.x(), w.torque.y(),
                                w.torque.z(), m_id) >= 0;  // DHD_MOTOR_SATURATED is > 0: taken
  }

 private:
  DeviceCapabilities m_capabilities;
  char m_id = -1;
};

}  // namespace

int main() {
  DeviceCapabilities limits;  // round values for an omega.6-class device; use your data sheet's
  limits.max_force = 12.0;
  limits.max_torque = 0.1;
  limits.max_stiffness = 14500.0;
  limits.workspace_min = Eigen::Vector3d(-0.08, -0.08, -0.06);
  limits.workspace_max = Eigen::Vector3d(0.08, 0.08, 0.06);
  limits.workspace_radius = 0.08;
  limits.nominal_rate = 1000.0;
  DhdDevice device(limits);
  return khz::example::run_spring(device);
}
