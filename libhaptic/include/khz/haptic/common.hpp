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

/// A force (N) and a torque (N·m, about the body's reference point), in world axes.
struct Wrench {
  Eigen::Vector3d force = Eigen::Vector3d::Zero();
  Eigen::Vector3d torque = Eigen::Vector3d::Zero();
};

}  // namespace khz::haptic
