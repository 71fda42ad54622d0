#include <khz/viewer/cursor_drag.hpp>
#include <khz/viewer/cursor_plane.hpp>

namespace khz::viewer {

CursorDrag::CursorDrag(const Eigen::Vector3d& start, const Eigen::AlignedBox3d& bounds,
                       double scroll_step)
    : m_bounds(bounds), m_scroll_step(scroll_step), m_target(clamped(start)) {}

Eigen::Vector3d CursorDrag::clamped(const Eigen::Vector3d& point) const noexcept {
  return point.cwiseMax(m_bounds.min()).cwiseMin(m_bounds.max());
}

void CursorDrag::press(const render::Camera& camera, const Eigen::Vector2d& pixel) noexcept {
  m_dragging = true;
  m_anchor = m_target;
  m_grab = cursor_on_plane(camera, pixel, m_anchor);
}

void CursorDrag::move(const render::Camera& camera, const Eigen::Vector2d& pixel) noexcept {
  if (!m_dragging) return;
  m_target = clamped(m_anchor + (cursor_on_plane(camera, pixel, m_anchor) - m_grab));
}

void CursorDrag::scroll(const render::Camera& camera, double notches) noexcept {
  const Eigen::Vector3d step = notches * m_scroll_step * camera.forward();
  m_target = clamped(m_target + step);
  m_anchor += step;
  m_grab += step;
}

}  // namespace khz::viewer
