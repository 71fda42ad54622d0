#include <khz/viewer/force_arrow.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace khz::viewer {

double ArrowScale::length(double force) const noexcept {
  if (!(force > 0.0)) return 0.0;
  return max_length * std::tanh(force * reference_length / (reference_force * max_length));
}

Eigen::Vector3d ArrowScale::arrow(const Eigen::Vector3d& force) const noexcept {
  const double magnitude = force.norm();
  if (!std::isfinite(magnitude) || !(magnitude > 0.0)) return Eigen::Vector3d::Zero();
  return force * (length(magnitude) / magnitude);
}

double view_half_extent(const render::Camera& camera, const Eigen::Vector3d& point) noexcept {
  const double depth = (point - camera.eye()).dot(camera.forward());
  if (!(depth > 0.0)) return 0.0;
  return depth * 0.5 * std::min(camera.width(), camera.height()) / camera.focal_length();
}

double room_in_view(const render::Camera& camera, const Eigen::Vector3d& from,
                    const Eigen::Vector3d& direction, double margin) noexcept {
  if (!from.allFinite() || !direction.allFinite() || !std::isfinite(margin)) return 0.0;
  // In view coordinates (right r, up u, forward d), the pixel x = W/2 + f r/d lies in
  // [margin, W − margin] iff (W/2 − margin) d ± f r ≥ 0 (d > 0), and likewise for y = H/2 − f u/d:
  // five half-spaces (with d ≥ near) linear along the ray, so each bounds t from one side.
  const Eigen::Vector3d start = camera.to_view(from);
  const Eigen::Vector3d step = camera.to_view(from + direction) - start;
  const double f = camera.focal_length();
  const double half_width = 0.5 * camera.width() - margin;
  const double half_height = 0.5 * camera.height() - margin;
  const auto inside = [&](const Eigen::Vector3d& v) {  // each ≥ 0 inside
    return std::array<double, 5>{half_width * v.z() + f * v.x(), half_width * v.z() - f * v.x(),
                                 half_height * v.z() + f * v.y(), half_height * v.z() - f * v.y(),
                                 v.z()};
  };
  std::array<double, 5> at_start = inside(start);
  at_start[4] -= camera.near_distance();
  const std::array<double, 5> slope = inside(step);
  double room = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < at_start.size(); ++i) {
    if (!(at_start[i] >= 0.0)) return 0.0;
    if (slope[i] < 0.0) room = std::min(room, at_start[i] / -slope[i]);
  }
  return room;
}

}  // namespace khz::viewer
