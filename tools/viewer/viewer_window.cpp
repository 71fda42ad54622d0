#include "viewer_window.hpp"

#include <khz/reduced/errors.hpp>
#include <khz/run/frame_renderer.hpp>

#define GLFW_INCLUDE_NONE
#include <GL/gl.h>
#include <GLFW/glfw3.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <utility>
#include <vector>

namespace khz::viewer {
namespace {

void report_glfw_error(int code, const char* description) {
  std::fprintf(stderr, "khz_viewer: GLFW error %d: %s\n", code, description);
}

}  // namespace

ViewerWindow::ViewerWindow(const std::string& title, int width, int height,
                           const run::SceneFraming& framing, CursorDrag& drag,
                           std::function<void(const Eigen::Vector3d&)> on_target)
    : m_orbit(framing, framing.turned(run::FrameOptions().view_direction),
              framing.turned(run::FrameOptions().up)),
      m_drag(drag),
      m_on_target(std::move(on_target)) {
  if (width < 16 || height < 16) throw reduced::Error("the window needs at least 16×16 pixels");
  glfwSetErrorCallback(report_glfw_error);
  if (glfwInit() != GLFW_TRUE) {
    throw reduced::Error(
        "cannot start GLFW: is there a display? (without one, try xvfb-run khz_viewer ...)");
  }
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 2);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 1);
  glfwWindowHint(GLFW_SAMPLES, 4);
  m_window = glfwCreateWindow(width, height, title.c_str(), nullptr, nullptr);
  if (m_window == nullptr) {
    glfwTerminate();
    throw reduced::Error("cannot open a window with an OpenGL 2.1 context");
  }
  glfwMakeContextCurrent(m_window);
  glfwSwapInterval(1);
  glfwSetWindowUserPointer(m_window, this);
  glfwGetWindowSize(m_window, &m_size.x(), &m_size.y());
  m_camera.emplace(m_orbit.camera(std::max(m_size.x(), 1), std::max(m_size.y(), 1)));

  // GLFW calls these from show_frame(), on this thread; none of them throws.
  glfwSetWindowSizeCallback(m_window, [](GLFWwindow* window, int w, int h) {
    ViewerWindow& self = of(window);
    self.m_size = {w, h};
    self.refit_camera();
  });
  glfwSetKeyCallback(m_window, [](GLFWwindow* window, int key, int, int action, int) {
    of(window).on_key(key, action);
  });
  glfwSetCharCallback(m_window, [](GLFWwindow* window, unsigned int character) {
    of(window).on_character(character);
  });
  glfwSetMouseButtonCallback(m_window, [](GLFWwindow* window, int button, int action, int) {
    of(window).on_button(button, action);
  });
  glfwSetCursorPosCallback(m_window, [](GLFWwindow* window, double x, double y) {
    of(window).on_cursor({x, y});
  });
  glfwSetScrollCallback(m_window, [](GLFWwindow* window, double sideways, double notches) {
    of(window).on_scroll(sideways, notches);
  });
}

ViewerWindow::~ViewerWindow() {
  glfwDestroyWindow(m_window);
  glfwTerminate();
}

ViewerWindow& ViewerWindow::of(GLFWwindow* window) noexcept {
  return *static_cast<ViewerWindow*>(glfwGetWindowUserPointer(window));
}

void ViewerWindow::refit_camera() noexcept {
  if (m_size.x() < 1 || m_size.y() < 1) return;  // minimized: keep the last camera
  try {
    m_camera.emplace(m_orbit.camera(m_size.x(), m_size.y()));
  } catch (const reduced::Error&) {
    // A size render::Camera refuses (beyond Image::max_size): keep the last camera.
  }
}

void ViewerWindow::on_key(int key, int action) noexcept {
  if (action != GLFW_PRESS) return;
  if (key == GLFW_KEY_ESCAPE) glfwSetWindowShouldClose(m_window, GLFW_TRUE);
  if (key == GLFW_KEY_HOME) {
    m_orbit.reset();
    refit_camera();
  }
}

void ViewerWindow::on_character(unsigned int character) noexcept {
  // Characters rather than key codes, so that + and - are found on any keyboard layout (the
  // keypad's too); a held key repeats.
  switch (character) {
    case '+':
    case '=':  // + without Shift on many layouts
      m_orbit.zoom(1.0);
      break;
    case '-':
      m_orbit.zoom(-1.0);
      break;
    case 'r':
    case 'R':
      m_orbit.reset();
      break;
    default:
      return;
  }
  refit_camera();
}

void ViewerWindow::on_button(int button, int action) noexcept {
  if (button == GLFW_MOUSE_BUTTON_LEFT) {
    if (action == GLFW_PRESS) m_drag.press(camera(), cursor());
    if (action == GLFW_RELEASE) m_drag.release();
  }
  if (button == GLFW_MOUSE_BUTTON_RIGHT) {
    m_orbiting = action == GLFW_PRESS;
    m_last_cursor = cursor();
  }
}

void ViewerWindow::on_cursor(const Eigen::Vector2d& position) noexcept {
  if (m_orbiting) {
    m_orbit.orbit(position - m_last_cursor);
    m_last_cursor = position;
    refit_camera();
  }
  if (m_drag.dragging()) {
    m_drag.move(camera(), position);
    target_moved();
  }
}

void ViewerWindow::on_scroll(double sideways, double notches) noexcept {
  const bool shift = glfwGetKey(m_window, GLFW_KEY_LEFT_SHIFT) == GLFW_PRESS ||
                     glfwGetKey(m_window, GLFW_KEY_RIGHT_SHIFT) == GLFW_PRESS;
  if (shift) {
    // Some systems turn Shift + wheel into sideways scrolling.
    m_orbit.zoom(notches != 0.0 ? notches : sideways);
    refit_camera();
    return;
  }
  m_drag.scroll(camera(), notches);
  target_moved();
}

bool ViewerWindow::closing() const noexcept { return glfwWindowShouldClose(m_window) != 0; }

Eigen::Vector2i ViewerWindow::framebuffer_size() const noexcept {
  Eigen::Vector2i size;
  glfwGetFramebufferSize(m_window, &size.x(), &size.y());
  return size;
}

Eigen::Vector2d ViewerWindow::cursor() const noexcept {
  Eigen::Vector2d position;
  glfwGetCursorPos(m_window, &position.x(), &position.y());
  return position;
}

render::Image ViewerWindow::read_frame() const {
  const Eigen::Vector2i size = framebuffer_size();
  const auto row_bytes = static_cast<std::size_t>(3 * size.x());
  std::vector<std::uint8_t> bottom_up(row_bytes * static_cast<std::size_t>(size.y()));
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadBuffer(GL_BACK);
  glReadPixels(0, 0, size.x(), size.y(), GL_RGB, GL_UNSIGNED_BYTE, bottom_up.data());
  render::Image image(size.x(), size.y());
  for (int y = 0; y < size.y(); ++y) {
    std::memcpy(image.bytes().data() + row_bytes * static_cast<std::size_t>(y),
                bottom_up.data() + row_bytes * static_cast<std::size_t>(size.y() - 1 - y),
                row_bytes);
  }
  return image;
}

void ViewerWindow::show_frame() noexcept {
  glfwSwapBuffers(m_window);
  glfwPollEvents();
}

}  // namespace khz::viewer
