#include <khz/reduced/errors.hpp>
#include <khz/viewer/orbit_camera.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

namespace khz::viewer {
namespace {

Eigen::Vector3d unit(const Eigen::Vector3d& v, const char* name) {
  const double length = v.norm();
  if (!v.allFinite() || !(length > 0.0)) {
    throw reduced::Error(std::string("OrbitCamera: ") + name + " must be finite and non-zero");
  }
  return v / length;
}

}  // namespace

OrbitCamera::OrbitCamera(const run::SceneFraming& framing, const Eigen::Vector3d& view_direction,
                         const Eigen::Vector3d& up, double radians_per_pixel)
    : m_framing(framing), m_up(unit(up, "up")), m_radians_per_pixel(radians_per_pixel) {
  const Eigen::Vector3d direction = unit(view_direction, "view_direction");
  const Eigen::Vector3d horizontal = direction - direction.dot(m_up) * m_up;
  // The same relative test as render::Camera's: no usable azimuth along `up`.
  if (horizontal.norm() < 1e-9) {
    throw reduced::Error("OrbitCamera: view_direction is parallel to up");
  }
  if (!std::isfinite(radians_per_pixel) || !(radians_per_pixel > 0.0)) {
    throw reduced::Error("OrbitCamera: radians_per_pixel must be finite and > 0");
  }
  m_forward = horizontal.normalized();
  m_side = m_up.cross(m_forward);
  m_start_elevation = std::clamp(std::asin(std::clamp(direction.dot(m_up), -1.0, 1.0)),
                                 -max_elevation, max_elevation);
  m_elevation = m_start_elevation;
}

Eigen::Vector3d OrbitCamera::direction() const noexcept {
  return std::cos(m_elevation) * (std::cos(m_azimuth) * m_forward + std::sin(m_azimuth) * m_side) +
         std::sin(m_elevation) * m_up;
}

render::Camera OrbitCamera::camera(int width, int height) const {
  const render::Camera fitted = m_framing.camera(direction(), m_up, width, height);
  const Eigen::Vector3d& centre = m_framing.centre;
  return render::Camera(centre + m_zoom * (fitted.eye() - centre), centre, m_up,
                        fitted.vertical_fov(), width, height);
}

void OrbitCamera::orbit(const Eigen::Vector2d& pixels) noexcept {
  if (!pixels.allFinite()) return;
  // A larger azimuth moves the eye along up × direction, the image's right: right is smaller.
  m_azimuth = std::remainder(m_azimuth - m_radians_per_pixel * pixels.x(), 2.0 * std::numbers::pi);
  m_elevation =
      std::clamp(m_elevation + m_radians_per_pixel * pixels.y(), -max_elevation, max_elevation);
}

void OrbitCamera::zoom(double notches) noexcept {
  if (!std::isfinite(notches)) return;
  m_zoom = std::clamp(m_zoom * std::pow(zoom_step, -notches), 1.0 / max_zoom, max_zoom);
}

void OrbitCamera::reset() noexcept {
  m_azimuth = 0.0;
  m_elevation = m_start_elevation;
  m_zoom = 1.0;
}

}  // namespace khz::viewer
