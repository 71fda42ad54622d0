#pragma once
// A region of space whose volume-mesh vertices a reduced model holds fixed (its anchors).

#include <Eigen/Core>
#include <khz/scene/export.hpp>

namespace khz::scene {

/// Selects the vertices of an object's volume mesh that are held fixed (the `fixed_vertices` of
/// the basis generators). Coordinates are in the object's body frame after scaling and centring
/// (metres), i.e. where the vertices are before the object's pose places it in the world.
///
/// JSON: {"type": "box", "min": [x, y, z], "max": [x, y, z]} or
///       {"type": "half_space", "point": [x, y, z], "normal": [x, y, z]}.
struct KHZ_SCENE_API AnchorRegion {
  enum class Kind {
    box,         ///< The closed axis-aligned box [min, max].
    half_space,  ///< The closed half-space the normal points into: (x − point) · normal ≥ 0.
  };
  Kind kind = Kind::box;
  Eigen::Vector3d min = Eigen::Vector3d::Zero();      ///< box: lower corner (m), ≤ max.
  Eigen::Vector3d max = Eigen::Vector3d::Zero();      ///< box: upper corner (m).
  Eigen::Vector3d point = Eigen::Vector3d::Zero();    ///< half_space: a point on its plane (m).
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();  ///< half_space: unit normal (normalized
                                                      ///< by the reader).

  /// True if the body-frame point `p` (m) lies in the region (boundary included).
  bool contains(const Eigen::Vector3d& p) const noexcept;
};

}  // namespace khz::scene
