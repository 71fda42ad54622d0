#pragma once
// Moving a world point with the mouse: drag it in the plane facing the camera, scroll it along
// the viewing axis (the viewer's manipulandum target).

#include <khz/render/camera.hpp>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace khz::viewer {

/// A target point (m, world) that follows the cursor while a button is held and moves along the
/// viewing axis with the scroll wheel; always kept inside a box. A drag is relative: pressing
/// does not move the target, and while the button is held the target moves by exactly what the
/// cursor's point moved on the plane through the target (at the press) facing the camera, so
/// the target stays under the same spot of the cursor at its depth. Pure; no display needed.
class CursorDrag {
 public:
  /// @param start the target's first position (m, world); clamped to `bounds`.
  /// @param bounds the box the target stays in (m, world), non-empty.
  /// @param scroll_step how far one scroll notch moves the target (m).
  CursorDrag(const Eigen::Vector3d& start, const Eigen::AlignedBox3d& bounds, double scroll_step);

  /// The target (m, world).
  const Eigen::Vector3d& target() const noexcept { return m_target; }
  /// Whether a drag is under way (between press() and release()).
  bool dragging() const noexcept { return m_dragging; }

  /// Starts a drag with the cursor at `pixel` (render::Camera's convention) in `camera`.
  void press(const render::Camera& camera, const Eigen::Vector2d& pixel) noexcept;
  /// The cursor moved to `pixel`: during a drag the target follows it in the drag's plane;
  /// otherwise nothing happens.
  void move(const render::Camera& camera, const Eigen::Vector2d& pixel) noexcept;
  /// Ends the drag; the target stays where it is.
  void release() noexcept { m_dragging = false; }
  /// Moves the target along camera.forward() by `notches` · scroll_step: positive notches
  /// (the wheel turned away from the user) push it away from the eye. During a drag the drag's
  /// plane moves with it.
  void scroll(const render::Camera& camera, double notches) noexcept;

 private:
  Eigen::Vector3d clamped(const Eigen::Vector3d& point) const noexcept;

  Eigen::AlignedBox3d m_bounds;
  double m_scroll_step;
  Eigen::Vector3d m_target;
  bool m_dragging = false;
  Eigen::Vector3d m_anchor = Eigen::Vector3d::Zero();  // the target when the drag began
  Eigen::Vector3d m_grab = Eigen::Vector3d::Zero();    // the cursor's point then, on the plane
};

}  // namespace khz::viewer
