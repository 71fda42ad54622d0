#pragma once
// How pictures of a running scene are framed: the scene's bounding sphere seen from a direction,
// just fitting the view (FrameRenderer's frames, the interactive viewer's window).

#include <khz/render/camera.hpp>
#include <khz/scene/scene_runtime.hpp>

#include <Eigen/Core>

#include <numbers>

namespace khz::run {

/// The vertical opening angle of scene cameras (rad).
inline constexpr double scene_vertical_fov = 35.0 * std::numbers::pi / 180.0;

/// Where a scene is: the bounding sphere of its objects' bounding box.
struct SceneFraming {
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();  ///< The box's centre (m, world).
  double radius = 1e-6;                              ///< Half its diagonal (m), at least 10⁻⁶.
  /// The scene's up (unit, world): against gravity in a scene with free objects (scene
  /// "dynamics"), whose world has a down; else y.
  Eigen::Vector3d up = Eigen::Vector3d::UnitY();

  /// `direction`, given for a scene whose up is y (e.g. FrameOptions' view), turned as y turns
  /// onto `up`.
  Eigen::Vector3d turned(const Eigen::Vector3d& direction) const;

  /// A camera looking at the centre from the side `view_direction` points to (world; any
  /// non-zero length, not parallel to `view_up`, the direction shown upwards) with
  /// scene_vertical_fov, from just far enough away that the sphere, 5 % enlarged, fits that
  /// angle, or that angle times width / height when the image is taller than wide.
  /// @param width, height Image size (pixels, as for render::Camera).
  /// @throws reduced::Error as render::Camera's constructor (a zero or non-finite direction, a
  ///         direction parallel to `view_up`, a size out of range).
  render::Camera camera(const Eigen::Vector3d& view_direction, const Eigen::Vector3d& view_up,
                        int width, int height) const;
};

/// The framing of every object's surface at its current pose (rest shapes, not deformed), and
/// the scene's up.
SceneFraming frame_scene(const scene::SceneRuntime& runtime);

}  // namespace khz::run
