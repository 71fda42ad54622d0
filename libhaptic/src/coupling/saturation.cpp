#include <khz/haptic/coupling/saturation.hpp>

#include <cmath>

namespace khz::haptic {

double saturation_profile(double magnitude, double plateau) noexcept {
  if (magnitude <= 0.5 * plateau) return magnitude;
  return plateau * (1.0 - 0.5 * std::exp(1.0 - 2.0 * magnitude / plateau));
}

SaturatedVector saturate(const Eigen::Vector3d& linear, double plateau) noexcept {
  SaturatedVector result;
  const double magnitude = linear.norm();
  if (magnitude <= 0.5 * plateau) {
    result.value = linear;
    return result;
  }
  const double decay = std::exp(1.0 - 2.0 * magnitude / plateau);  // f′(m)
  const double value = plateau * (1.0 - 0.5 * decay);              // f(m)
  const double ratio = value / magnitude;
  const Eigen::Vector3d direction = linear / magnitude;
  result.value = ratio * linear;
  result.jacobian =
      ratio * Eigen::Matrix3d::Identity() + (decay - ratio) * direction * direction.transpose();
  result.saturated = true;
  return result;
}

}  // namespace khz::haptic
