#pragma once
// Limiting a vector's magnitude, as the coupling and the devices do (private to libhaptic).

#include <Eigen/Core>

#include <cmath>

namespace khz::haptic::detail {

/// |v| by std::hypot, a function of the three values alone: Eigen's stableNorm() of a Vector3d
/// sums in an order that depends on the vector's address (it splits at the first SIMD-aligned
/// coefficient), so a threshold test on it could pass or fail depending on the caller's stack.
inline double magnitude(const Eigen::Vector3d& v) noexcept {
  return std::hypot(v.x(), v.y(), v.z());
}

/// Scales `v` down to magnitude `limit` if it is longer (magnitude()), keeping its direction;
/// returns whether it did.
inline bool clamp_magnitude(Eigen::Vector3d& v, double limit) noexcept {
  const double magnitude = detail::magnitude(v);
  if (magnitude <= limit) return false;
  v *= limit / magnitude;
  return true;
}

}  // namespace khz::haptic::detail
