#pragma once
// A pinhole perspective camera: world points to pixel coordinates and depth.

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <optional>

namespace khz::render {

/// Where a world point lands in the image.
struct ScreenPoint {
  /// x to the right, y down, in pixels. Pixel (i, j) covers [i, i+1) × [j, j+1), so its centre is
  /// (i + 0.5, j + 0.5). Points outside the field of view land outside [0, width) × [0, height).
  Eigen::Vector2d pixel;
  /// Distance from the eye along the viewing axis, world units; at least Camera::near_distance().
  double depth;
};

/// A pinhole camera at `eye` looking at `target`, with square pixels and the principal point at
/// the image centre. World units are whatever the scene uses (a mesh keeps its file's units).
/// View coordinates are (right, up, forward) in world units with the eye at the origin; depth is
/// the forward coordinate. Immutable once built.
class Camera {
 public:
  /// @param eye Eye position, world units.
  /// @param target The point that projects to the image centre; must differ from `eye`.
  /// @param up A world direction that appears upwards in the image; need not be perpendicular
  ///        to the viewing direction, must not be parallel to it.
  /// @param vertical_fov Full vertical opening angle, radians, in (0, π).
  /// @param width Image width, pixels, in [1, Image::max_size].
  /// @param height Image height, pixels, in [1, Image::max_size].
  /// @throws khz::reduced::Error naming the offending parameter if a vector is not finite,
  ///         eye = target, up is zero or parallel to the viewing direction, or a size or the
  ///         angle is out of range.
  Camera(const Eigen::Vector3d& eye, const Eigen::Vector3d& target, const Eigen::Vector3d& up,
         double vertical_fov, int width, int height);

  const Eigen::Vector3d& eye() const noexcept { return m_eye; }
  const Eigen::Vector3d& target() const noexcept { return m_target; }
  /// Unit vector pointing right in the image.
  const Eigen::Vector3d& right() const noexcept { return m_right; }
  /// Unit vector pointing up in the image (`up` made perpendicular to forward()).
  const Eigen::Vector3d& up() const noexcept { return m_up; }
  /// Unit viewing direction, from eye towards target.
  const Eigen::Vector3d& forward() const noexcept { return m_forward; }
  /// Full vertical opening angle, radians.
  double vertical_fov() const noexcept { return m_vertical_fov; }
  int width() const noexcept { return m_width; }
  int height() const noexcept { return m_height; }
  /// Focal length in pixels: height / (2 tan(vertical_fov / 2)).
  double focal_length() const noexcept { return m_focal_length; }
  /// Geometry nearer to the eye than this (world units) is clipped away: 10⁻³ |target − eye|,
  /// far nearer than anything a camera aimed at the target normally frames.
  double near_distance() const noexcept { return m_near_distance; }

  /// A world point in view coordinates (right, up, forward), world units.
  Eigen::Vector3d to_view(const Eigen::Vector3d& world) const noexcept;
  /// Pixel coordinates of a point given in view coordinates with forward coordinate > 0.
  Eigen::Vector2d view_to_pixel(const Eigen::Vector3d& view) const noexcept;
  /// Projects a world point. Empty if the point is not finite or is nearer than
  /// near_distance() along the viewing axis (which includes everything behind the eye).
  std::optional<ScreenPoint> project(const Eigen::Vector3d& world) const noexcept;

 private:
  Eigen::Vector3d m_eye;
  Eigen::Vector3d m_target;
  Eigen::Vector3d m_right;
  Eigen::Vector3d m_up;
  Eigen::Vector3d m_forward;
  double m_vertical_fov;
  int m_width;
  int m_height;
  double m_focal_length;
  double m_near_distance;
};

/// A camera that looks along `view_direction` at the centre of `box` from just far enough away
/// that all eight corners project inside the image, leaving at least `margin` of the image's
/// half-width and half-height free on every side (so the whole box, and anything inside it, is
/// visible). The distance is exact for the box, not for its bounding sphere, so the box fills
/// the frame along its tightest image direction. A box with no extent (a single point) is
/// viewed from unit distance.
/// @param box World-space box, non-empty and finite.
/// @param view_direction Direction the camera looks in, any non-zero length.
/// @param up World direction that should appear upwards; when it is parallel to
///        `view_direction`, a perpendicular one is chosen instead.
/// @param vertical_fov, width, height As for Camera.
/// @param margin Fraction of the half-width and half-height kept free, in [0, 1).
/// @throws khz::reduced::Error naming the parameter if the box is empty or not finite,
///         view_direction is zero or not finite, margin is out of range, or Camera's
///         conditions fail.
Camera frame_box(const Eigen::AlignedBox3d& box, const Eigen::Vector3d& view_direction,
                 const Eigen::Vector3d& up, double vertical_fov, int width, int height,
                 double margin = 0.05);

}  // namespace khz::render
