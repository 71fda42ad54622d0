#pragma once
// The viewer's camera: orbiting around the scene's centre and zooming towards it, starting from
// (and reset to) the framing of the frame pictures.

#include <khz/render/camera.hpp>
#include <khz/run/scene_framing.hpp>

#include <Eigen/Core>

#include <numbers>

namespace khz::viewer {

/// A camera that always looks at the scene's centre (run::SceneFraming::centre) with the world
/// direction `up` shown upwards. Where the eye is: a direction from the centre, given by an
/// azimuth about `up` and an elevation above the plane perpendicular to it, and a distance, the
/// framing's (SceneFraming::camera(): the scene's sphere just fits the view) times a zoom
/// factor. Orbiting turns the direction and keeps the distance; zooming scales the distance and
/// keeps the direction. Pure; no display needed.
class OrbitCamera {
 public:
  /// The elevation stays within ±this (rad, 89°): at ±90° the view would look along `up`, which
  /// render::Camera refuses.
  static constexpr double max_elevation = 89.0 * std::numbers::pi / 180.0;
  /// The zoom factor stays within [1 / max_zoom, max_zoom]: from well inside the scene to where
  /// it is a speck.
  static constexpr double max_zoom = 20.0;
  /// Per notch, zoom() divides the distance by this.
  static constexpr double zoom_step = 1.15;

  /// The start (and reset()) view: from the side `view_direction` points to, as
  /// SceneFraming::camera(), at zoom factor 1.
  /// @param framing where the scene is.
  /// @param view_direction from the centre towards the eye (world; any non-zero length, not
  ///        parallel to `up`); an elevation beyond ±max_elevation is clamped.
  /// @param up the world direction shown upwards (non-zero).
  /// @param radians_per_pixel how far orbit() turns per pixel of cursor motion (rad, > 0).
  /// @throws reduced::Error if a direction is zero or not finite, `view_direction` is parallel
  ///         to `up`, or `radians_per_pixel` is not finite and > 0.
  OrbitCamera(const run::SceneFraming& framing, const Eigen::Vector3d& view_direction,
              const Eigen::Vector3d& up, double radians_per_pixel = 0.01);

  /// The camera for an image of `width` × `height` pixels (render::Camera's ranges).
  /// @throws reduced::Error as render::Camera for a size out of range.
  render::Camera camera(int width, int height) const;

  /// Turns the view as if the cursor, moved by `pixels` (x right, y down), dragged the scene
  /// around its centre: right turns the scene to the right (the eye goes left, the azimuth
  /// decreases), down tips its top towards the viewer (the eye rises). The elevation stops at
  /// ±max_elevation. Non-finite motion is ignored.
  void orbit(const Eigen::Vector2d& pixels) noexcept;
  /// Moves the eye towards the centre by a factor zoom_step per notch (positive notches: nearer,
  /// the scene larger; negative: farther), within the zoom factor's range. Non-finite notches
  /// are ignored.
  void zoom(double notches) noexcept;
  /// Back to the start view (direction and zoom factor 1).
  void reset() noexcept;

  /// The azimuth about `up` (rad, measured from the start view's), and the elevation (rad).
  double azimuth() const noexcept { return m_azimuth; }
  double elevation() const noexcept { return m_elevation; }
  /// The eye's distance over the framing's.
  double zoom_factor() const noexcept { return m_zoom; }
  /// The unit direction from the centre towards the eye.
  Eigen::Vector3d direction() const noexcept;

 private:
  run::SceneFraming m_framing;
  Eigen::Vector3d m_up;       // unit
  Eigen::Vector3d m_forward;  // unit, ⟂ m_up: the start view's horizontal direction (azimuth 0)
  Eigen::Vector3d m_side;     // m_up × m_forward (azimuth π/2)
  double m_radians_per_pixel;
  double m_start_elevation;
  double m_azimuth = 0.0;
  double m_elevation = 0.0;
  double m_zoom = 1.0;
};

}  // namespace khz::viewer
