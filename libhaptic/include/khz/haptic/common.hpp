#pragma once
// What every part of libhaptic shares: rigid poses and wrenches, and libreduced's exceptions.

#include <khz/reduced/errors.hpp>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace khz::haptic {

using reduced::Error;
using reduced::IoError;
using reduced::ParseError;

/// A rigid placement: the world position (m) of a body's reference point (the grasp point of a
/// haptic object, the tool point of a device) and the unit quaternion turning body axes into
/// world axes.
struct Pose {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
};

/// Where a body held at its point `grasp_in_body` (m, body frame) is when its grasp frame is
/// `grasp`: world ← body, orientations coinciding and the grasp point at grasp.position. With a
/// zero grasp point, `grasp` itself as a rigid transform.
inline Eigen::Isometry3d held_body_pose(const Pose& grasp,
                                        const Eigen::Vector3d& grasp_in_body) noexcept {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = grasp.orientation.normalized().toRotationMatrix();
  pose.translation() = grasp.position - pose.linear() * grasp_in_body;
  return pose;
}

/// A force (N) and a torque (N·m, about the body's reference point), in world axes.
struct Wrench {
  Eigen::Vector3d force = Eigen::Vector3d::Zero();
  Eigen::Vector3d torque = Eigen::Vector3d::Zero();
};

}  // namespace khz::haptic
