#pragma once
// Limiting a vector's magnitude, as the coupling and the devices do (private to libhaptic).

#include <Eigen/Core>

#include <cmath>

namespace khz::haptic::detail {

/// Scales `v` down to magnitude `limit` if it is longer, keeping its direction; returns whether it
/// did. The magnitude is std::hypot's, a function of the three values alone: Eigen's
/// stableNorm() of a Vector3d sums in an order that depends on the vector's address (it splits
/// at the first SIMD-aligned coefficient), so the same wrench could be clamped or not depending
/// on the caller's stack.
inline bool clamp_magnitude(Eigen::Vector3d& v, double limit) noexcept {
  const double magnitude = std::hypot(v.x(), v.y(), v.z());
  if (magnitude <= limit) return false;
  v *= limit / magnitude;
  return true;
}

}  // namespace khz::haptic::detail
