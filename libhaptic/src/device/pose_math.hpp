#pragma once
// Small pose and wrench helpers the device implementations share (private to libhaptic).

#include <khz/haptic/common.hpp>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cmath>

namespace khz::haptic::detail {

/// Largest |‖q‖ − 1| a reading's orientation may show before it counts as malformed.
inline constexpr double unit_quaternion_tolerance = 1e-3;

inline bool is_finite(const Wrench& wrench) noexcept {
  return wrench.force.allFinite() && wrench.torque.allFinite();
}

/// True if the position is finite and the orientation a finite quaternion of norm 1 within
/// unit_quaternion_tolerance.
inline bool is_valid_pose(const Pose& pose) noexcept {
  return pose.position.allFinite() && pose.orientation.coeffs().allFinite() &&
         std::abs(pose.orientation.norm() - 1.0) <= unit_quaternion_tolerance;
}

/// The rotation vector (axis · angle, angle in [0, π]) of a unit quaternion.
inline Eigen::Vector3d rotation_vector(const Eigen::Quaterniond& q) noexcept {
  const double w = q.w() < 0.0 ? -q.w() : q.w();
  const Eigen::Vector3d v = q.w() < 0.0 ? Eigen::Vector3d(-q.vec()) : Eigen::Vector3d(q.vec());
  const double s = v.norm();
  if (s < 1e-12) return 2.0 * v;  // first order; exact enough below 1e-12 rad
  return (2.0 * std::atan2(s, w) / s) * v;
}

/// The unit quaternion of a rotation vector (axis · angle).
inline Eigen::Quaterniond quaternion_from_rotation_vector(const Eigen::Vector3d& r) noexcept {
  const double angle = r.norm();
  if (angle < 1e-12) return Eigen::Quaterniond(1.0, 0.5 * r.x(), 0.5 * r.y(), 0.5 * r.z());
  return Eigen::Quaterniond(Eigen::AngleAxisd(angle, r / angle));
}

}  // namespace khz::haptic::detail
