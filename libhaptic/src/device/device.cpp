#include <khz/haptic/device/device.hpp>

#include <cmath>

namespace khz::haptic {
namespace {

void require(bool condition, const DeviceCapabilities& capabilities, const std::string& what) {
  if (!condition) throw Error("device '" + capabilities.name + "': " + what);
}

}  // namespace

Device::~Device() = default;

bool DeviceCapabilities::contains(const Eigen::Vector3d& p) const noexcept {
  const Eigen::Vector3d centre = 0.5 * (workspace_min + workspace_max);
  return (p.array() >= workspace_min.array()).all() && (p.array() <= workspace_max.array()).all() &&
         (p - centre).norm() <= workspace_radius;
}

void DeviceCapabilities::validate() const {
  require(input_dof == 3 || input_dof == 6, *this,
          "input_dof must be 3 or 6, not " + std::to_string(input_dof));
  require(output_dof == 0 || output_dof == 3 || output_dof == 6, *this,
          "output_dof must be 0, 3 or 6, not " + std::to_string(output_dof));
  require(std::isfinite(max_force) && max_force > 0.0, *this,
          "max_force must be finite and > 0 (N)");
  require(output_dof < 6 || (std::isfinite(max_torque) && max_torque > 0.0), *this,
          "max_torque must be finite and > 0 (N·m) for a 6-DOF output device");
  require(std::isfinite(max_stiffness) && max_stiffness > 0.0, *this,
          "max_stiffness must be finite and > 0 (N/m)");
  require(workspace_min.allFinite() && workspace_max.allFinite() &&
              (workspace_min.array() < workspace_max.array()).all(),
          *this, "the workspace box must be finite with workspace_min < workspace_max");
  require(!std::isnan(workspace_radius) && workspace_radius > 0.0, *this,
          "workspace_radius must be > 0 (m; infinity for none)");
  require(std::isfinite(nominal_rate) && nominal_rate > 0.0, *this,
          "nominal_rate must be finite and > 0 (Hz)");
}

}  // namespace khz::haptic
