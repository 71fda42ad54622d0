#include <khz/render/camera.hpp>

#include <khz/reduced/errors.hpp>
#include <khz/render/image.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

namespace khz::render {
namespace {

void require_finite(const Eigen::Vector3d& v, const char* name) {
  if (!v.allFinite()) throw reduced::Error(std::string("camera: ") + name + " is not finite");
}

void require_size(int value, const char* name) {
  if (value < 1 || value > Image::max_size) {
    throw reduced::Error(std::string("camera: ") + name + " " + std::to_string(value) +
                         " is not in [1, " + std::to_string(Image::max_size) + "]");
  }
}

}  // namespace

Camera::Camera(const Eigen::Vector3d& eye, const Eigen::Vector3d& target, const Eigen::Vector3d& up,
               double vertical_fov, int width, int height)
    : m_eye(eye), m_target(target), m_vertical_fov(vertical_fov), m_width(width), m_height(height) {
  require_finite(eye, "eye");
  require_finite(target, "target");
  require_finite(up, "up");
  require_size(width, "width");
  require_size(height, "height");
  if (!(vertical_fov > 0.0 && vertical_fov < std::numbers::pi)) {
    throw reduced::Error("camera: vertical_fov " + std::to_string(vertical_fov) +
                         " rad is not in (0, π)");
  }
  const double distance = (target - eye).norm();
  if (!(distance > 0.0)) throw reduced::Error("camera: eye and target coincide");
  m_forward = (target - eye) / distance;
  const Eigen::Vector3d right = m_forward.cross(up);
  // Relative test: an up vector within ~1e-9 rad of the viewing axis leaves no usable roll.
  if (!(right.norm() > 1e-9 * up.norm())) {
    throw reduced::Error("camera: up is zero or parallel to the viewing direction");
  }
  m_right = right.normalized();
  m_up = m_right.cross(m_forward);
  m_focal_length = 0.5 * height / std::tan(0.5 * vertical_fov);
  m_near_distance = 1e-3 * distance;
}

Eigen::Vector3d Camera::to_view(const Eigen::Vector3d& world) const noexcept {
  const Eigen::Vector3d d = world - m_eye;
  return {d.dot(m_right), d.dot(m_up), d.dot(m_forward)};
}

Eigen::Vector2d Camera::view_to_pixel(const Eigen::Vector3d& view) const noexcept {
  const double scale = m_focal_length / view.z();
  return {0.5 * m_width + scale * view.x(), 0.5 * m_height - scale * view.y()};
}

std::optional<ScreenPoint> Camera::project(const Eigen::Vector3d& world) const noexcept {
  if (!world.allFinite()) return std::nullopt;
  const Eigen::Vector3d view = to_view(world);
  if (!(view.z() >= m_near_distance)) return std::nullopt;
  return ScreenPoint{view_to_pixel(view), view.z()};
}

Camera frame_box(const Eigen::AlignedBox3d& box, const Eigen::Vector3d& view_direction,
                 const Eigen::Vector3d& up, double vertical_fov, int width, int height,
                 double margin) {
  if (box.isEmpty() || !box.min().allFinite() || !box.max().allFinite()) {
    throw reduced::Error("frame_box: the box is empty or not finite");
  }
  if (!view_direction.allFinite() || !(view_direction.norm() > 0.0)) {
    throw reduced::Error("frame_box: view_direction is zero or not finite");
  }
  if (!(margin >= 0.0 && margin < 1.0)) {
    throw reduced::Error("frame_box: margin " + std::to_string(margin) + " is not in [0, 1)");
  }
  require_finite(up, "up");
  const Eigen::Vector3d forward = view_direction.normalized();
  Eigen::Vector3d camera_up = up;
  if (!(forward.cross(up).norm() > 1e-9 * up.norm())) {
    // Any perpendicular will do: take the world axis least aligned with the view.
    Eigen::Index axis = 0;
    forward.cwiseAbs().minCoeff(&axis);
    camera_up = forward.cross(Eigen::Vector3d::Unit(axis));
  }
  // A throwaway camera at unit distance gives the view frame and validates the rest.
  const Eigen::Vector3d centre = box.center();
  const Camera probe(centre - forward, centre, camera_up, vertical_fov, width, height);

  // A corner at view offset (x, y, z) from the centre seen from distance D projects inside the
  // free area iff |x| ≤ (D + z) tan_x and |y| ≤ (D + z) tan_y; take the largest D any corner needs.
  const double tan_y = (1.0 - margin) * std::tan(0.5 * vertical_fov);
  const double tan_x = tan_y * width / height;
  const double diagonal = box.diagonal().norm();
  double distance = 0.0;
  double nearest = 0.0;  // largest distance of a corner in front of the centre
  for (int i = 0; i < 8; ++i) {
    const Eigen::Vector3d offset =
        probe.to_view(box.corner(static_cast<Eigen::AlignedBox3d::CornerType>(i))) -
        Eigen::Vector3d(0.0, 0.0, 1.0);
    distance =
        std::max(distance,
                 std::max(std::abs(offset.x()) / tan_x, std::abs(offset.y()) / tan_y) - offset.z());
    nearest = std::max(nearest, -offset.z());
  }
  // Keep the nearest corner well in front of the near plane (10⁻³ of the distance), which a box
  // seen exactly along one of its edges would otherwise touch.
  distance = std::max(distance, nearest + 0.01 * diagonal);
  if (diagonal == 0.0) distance = 1.0;
  return Camera(centre - distance * forward, centre, camera_up, vertical_fov, width, height);
}

}  // namespace khz::render
