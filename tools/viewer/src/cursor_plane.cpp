#include <khz/viewer/cursor_plane.hpp>

namespace khz::viewer {

Eigen::Vector3d cursor_on_plane(const render::Camera& camera, const Eigen::Vector2d& pixel,
                                const Eigen::Vector3d& plane_point) noexcept {
  // The ray's direction with unit forward component (the inverse of view_to_pixel()), so the
  // plane at depth d is reached at eye + d · direction.
  const Eigen::Vector2d offset =
      (pixel - 0.5 * Eigen::Vector2d(camera.width(), camera.height())) / camera.focal_length();
  const Eigen::Vector3d direction =
      camera.forward() + offset.x() * camera.right() - offset.y() * camera.up();
  const double depth = (plane_point - camera.eye()).dot(camera.forward());
  return camera.eye() + depth * direction;
}

}  // namespace khz::viewer
