#pragma once
// The viewer's window (GLFW, an OpenGL 2.1 context): the orbit camera at the window's size, and
// the mouse and keys turned into the manipulandum's target and the camera's moves.

#include <khz/render/camera.hpp>
#include <khz/render/image.hpp>
#include <khz/run/scene_framing.hpp>
#include <khz/viewer/cursor_drag.hpp>
#include <khz/viewer/orbit_camera.hpp>

#include <Eigen/Core>

#include <functional>
#include <optional>
#include <string>

struct GLFWwindow;

namespace khz::viewer {

/// A window showing the scene through an OrbitCamera that starts from run::FrameRenderer's
/// framing (its default view direction and up) and is refitted whenever the window's size
/// changes. The left button drags the manipulandum's target in the plane facing the camera, the
/// scroll wheel moves it along the viewing axis (CursorDrag); every change is passed to
/// `on_target`. The right button orbits the camera around the scene's centre, Shift with the
/// wheel and the + and - keys (main row or keypad; = as +) zoom, R or Home resets the view. Esc or
/// closing the window asks to quit. Belongs to the thread that made it (GLFW's main-thread
/// rule).
class ViewerWindow {
 public:
  /// Opens the window with its OpenGL context current.
  /// @param width, height the window's size (screen coordinates), ≥ 16.
  /// @param framing where the scene is (run::frame_scene()).
  /// @param drag the target the mouse moves; must outlive the window.
  /// @param on_target called (on this thread) with the target (m, world) after every change.
  /// @throws reduced::Error if GLFW cannot start (no display) or make the window.
  ViewerWindow(const std::string& title, int width, int height, const run::SceneFraming& framing,
               CursorDrag& drag, std::function<void(const Eigen::Vector3d&)> on_target);
  ~ViewerWindow();
  ViewerWindow(const ViewerWindow&) = delete;
  ViewerWindow& operator=(const ViewerWindow&) = delete;

  /// True once Esc was pressed or the window closed.
  bool closing() const noexcept;
  /// The camera of the window's current size (cursor positions are in its pixels).
  const render::Camera& camera() const noexcept { return *m_camera; }
  /// The framebuffer's size (pixels; differs from the window's on high-density screens).
  Eigen::Vector2i framebuffer_size() const noexcept;
  /// The frame drawn but not yet shown (the back buffer) as an image.
  render::Image read_frame() const;
  /// Shows the frame drawn and handles the events that came in meanwhile.
  void show_frame() noexcept;

 private:
  static ViewerWindow& of(GLFWwindow* window) noexcept;
  /// Makes m_camera anew from the orbit camera at the window's size (kept while minimized).
  void refit_camera() noexcept;
  void on_key(int key, int action) noexcept;
  void on_character(unsigned int character) noexcept;
  void on_button(int button, int action) noexcept;
  void on_cursor(const Eigen::Vector2d& position) noexcept;
  void on_scroll(double sideways, double notches) noexcept;
  Eigen::Vector2d cursor() const noexcept;
  void target_moved() const { m_on_target(m_drag.target()); }

  GLFWwindow* m_window = nullptr;
  OrbitCamera m_orbit;
  CursorDrag& m_drag;
  std::function<void(const Eigen::Vector3d&)> m_on_target;
  std::optional<render::Camera> m_camera;
  Eigen::Vector2i m_size{1, 1};             // the window's (screen coordinates)
  bool m_orbiting = false;                  // the right button is held
  Eigen::Vector2d m_last_cursor{0.0, 0.0};  // while orbiting
};

}  // namespace khz::viewer
