#pragma once
// The world point under the mouse cursor, on a plane facing the camera.

#include <khz/render/camera.hpp>

#include <Eigen/Core>

namespace khz::viewer {

/// Where the ray from the camera's eye through the cursor meets the plane through
/// `plane_point` perpendicular to the viewing direction (camera.forward()): the world point
/// (m) drawn under the cursor at that plane's depth. Pure; no display needed.
/// @param camera the camera the window shows (render::Camera's pixel convention: x to the
///        right and y down from the image's top-left corner, the image centre at (width/2,
///        height/2), as GLFW reports cursor positions in a window of that size).
/// @param pixel the cursor position (pixels; may lie outside the image).
/// @param plane_point any point of the plane (m, world), in front of the eye.
/// @returns a point whose depth along camera.forward() equals plane_point's; the image
///          centre gives the plane's point on the viewing axis, and a pixel offset (dx, dy)
///          moves it by (dx · right − dy · up) · depth / focal length.
Eigen::Vector3d cursor_on_plane(const render::Camera& camera, const Eigen::Vector2d& pixel,
                                const Eigen::Vector3d& plane_point) noexcept;

}  // namespace khz::viewer
