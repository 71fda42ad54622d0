#pragma once
// Rotation vectors and unit quaternions: the exponential and logarithm maps the virtual coupling
// turns the simulation object with, and eq. 4.15's positive hemisphere (thesis §4.3).

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cmath>

namespace khz::haptic {

/// toPositiveHemisphere of eq. 4.15: q if its scalar part is ≥ 0, else −q (the same rotation).
/// On the hemispheres' border (scalar part 0, a half turn) q and −q are both "positive"; the one
/// whose first nonzero vector component is positive is taken, so q and −q map to one quaternion
/// everywhere and the coupling torque of a half turn does not depend on the sign a caller chose.
inline Eigen::Quaterniond to_positive_hemisphere(const Eigen::Quaterniond& q) noexcept {
  bool flip = q.w() < 0.0;
  if (q.w() == 0.0) {
    flip = q.x() < 0.0 || (q.x() == 0.0 && (q.y() < 0.0 || (q.y() == 0.0 && q.z() < 0.0)));
  }
  return flip ? Eigen::Quaterniond(-q.w(), -q.x(), -q.y(), -q.z()) : q;
}

/// The exponential map: the unit quaternion of the rotation by ‖w‖ rad about w/‖w‖ (any ‖w‖).
/// Applied on the left, exp(Δω)·q turns a body by Δω in world axes.
inline Eigen::Quaterniond rotation_quaternion(const Eigen::Vector3d& w) noexcept {
  const double angle = w.norm();
  // sin(angle/2)/angle, by its series near 0 (the next term, angle⁴/3840, is below 1e-19 there).
  const double s = angle < 1e-4 ? 0.5 - angle * angle / 48.0 : std::sin(0.5 * angle) / angle;
  return Eigen::Quaterniond(std::cos(0.5 * angle), s * w.x(), s * w.y(), s * w.z());
}

/// The logarithm map: the rotation vector θ·a (θ ∈ [0, π], a the unit axis) of the unit
/// quaternion q, taken on the positive hemisphere, so rotation_quaternion(rotation_vector(q))
/// is ±q and the rotation is the short way round.
inline Eigen::Vector3d rotation_vector(const Eigen::Quaterniond& q) noexcept {
  const Eigen::Quaterniond p = to_positive_hemisphere(q);
  const double s = p.vec().norm();  // sin(θ/2)
  // θ/sin(θ/2) = 2·atan2(s, w)/s, which tends to 2/w (relative error s²/3) as s → 0.
  const double factor = s < 1e-8 ? 2.0 / p.w() : 2.0 * std::atan2(s, p.w()) / s;
  return factor * p.vec();
}

}  // namespace khz::haptic
