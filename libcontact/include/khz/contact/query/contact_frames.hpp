#pragma once
// Where the two objects of a contact query are.

#include <khz/contact/export.hpp>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace khz::contact {

/// The poses of a query's two objects and the haptic object's grasp point.
struct KHZ_CONTACT_API ContactFrames {
  /// World ← pointshell body (the frame the tree's points are given in).
  Eigen::Isometry3d pointshell = Eigen::Isometry3d::Identity();
  /// World ← field body (the frame the field is queried in).
  Eigen::Isometry3d field = Eigen::Isometry3d::Identity();
  /// Grasp point of the haptic object (m, world): the torque's reference point and the centre of
  /// the rotations the gradients are taken for.
  Eigen::Vector3d grasp_point = Eigen::Vector3d::Zero();
};

}  // namespace khz::contact
