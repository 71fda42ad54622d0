#include <khz/haptic/common.hpp>
#include <khz/haptic/world/dynamics_options.hpp>

#include <cmath>
#include <string>

namespace khz::haptic {

void DynamicsOptions::validate() const {
  if (!gravity.allFinite()) throw Error("DynamicsOptions: gravity must be finite (m/s²)");
  if (!(std::isfinite(time_step) && time_step > 0.0)) {
    throw Error("DynamicsOptions: time_step must be finite and > 0 (s), got " +
                std::to_string(time_step));
  }
  if (!(std::isfinite(contact_damping) && contact_damping >= 0.0)) {
    throw Error("DynamicsOptions: contact_damping must be finite and >= 0 (s), got " +
                std::to_string(contact_damping));
  }
  if (!(std::isfinite(sleep_speed) && sleep_speed >= 0.0)) {
    throw Error("DynamicsOptions: sleep_speed must be finite and >= 0 (m/s), got " +
                std::to_string(sleep_speed));
  }
  if (!(std::isfinite(sleep_time) && sleep_time >= 0.0)) {
    throw Error("DynamicsOptions: sleep_time must be finite and >= 0 (s), got " +
                std::to_string(sleep_time));
  }
}

}  // namespace khz::haptic
