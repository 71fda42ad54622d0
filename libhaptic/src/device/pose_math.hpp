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

}  // namespace khz::haptic::detail
