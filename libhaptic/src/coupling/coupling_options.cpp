#include <khz/haptic/coupling/coupling_options.hpp>

#include <cmath>
#include <string>

namespace khz::haptic {
namespace {

void require(bool valid, const char* name, double value, const char* expected) {
  if (!valid) {
    throw Error(std::string("CouplingOptions: ") + name + " must be " + expected + ", got " +
                std::to_string(value));
  }
}

bool finite_positive(double value) { return std::isfinite(value) && value > 0.0; }

}  // namespace

CouplingSprings CouplingOptions::springs() const noexcept {
  return {stiffness, torque_stiffness, saturation_force, saturation_force * object_radius};
}

void CouplingOptions::validate() const {
  require(finite_positive(stiffness), "stiffness", stiffness, "finite and > 0 (N/m)");
  require(finite_positive(torque_stiffness), "torque_stiffness", torque_stiffness,
          "finite and > 0 (N·m)");
  require(static_damping >= 0.0 && static_damping < 1.0, "static_damping", static_damping,
          "in [0, 1)");
  require(finite_positive(period), "period", period, "finite and > 0 (s)");
  // Limits: > 0, or +∞ for none (NaN fails).
  const struct {
    const char* name;
    double value;
    const char* expected;
  } limits[] = {
      {"max_speed", max_speed, "> 0 (m/s) or unlimited"},
      {"max_angular_speed", max_angular_speed, "> 0 (rad/s) or unlimited"},
      {"saturation_force", saturation_force, "> 0 (N) or unlimited"},
      {"object_radius", object_radius, "> 0 (m) or unlimited"},
      {"max_rendered_force", max_rendered_force, "> 0 (N) or unlimited"},
      {"max_rendered_torque", max_rendered_torque, "> 0 (N·m) or unlimited"},
      {"device_max_stiffness", device_max_stiffness, "> 0 (N/m) or unlimited"},
  };
  for (const auto& limit : limits) {
    require(limit.value > 0.0, limit.name, limit.value, limit.expected);
  }
  require(stiffness <= device_max_stiffness, "stiffness", stiffness,
          "≤ device_max_stiffness: k_VC bounds the stiffness the device renders (thesis §4.7, "
          "eq. 4.31)");
  require(degenerate_threshold > 0.0 && degenerate_threshold < 1.0, "degenerate_threshold",
          degenerate_threshold, "in (0, 1)");
  require(rotation_length == 0.0 || finite_positive(rotation_length), "rotation_length",
          rotation_length, "finite and > 0 (m/rad), or 0 for object_radius (1 m if unlimited)");
}

}  // namespace khz::haptic
