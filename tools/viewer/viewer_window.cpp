#include "viewer_window.hpp"

#include <khz/reduced/errors.hpp>
#include <khz/run/frame_renderer.hpp>

#define GLFW_INCLUDE_NONE
#include <GL/gl.h>
#include <GLFW/glfw3.h>

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
    : m_framing(framing), m_drag(drag), m_on_target(std::move(on_target)) {
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
  glfwGetWindowSize(m_window, &width, &height);
  fit_camera(width, height);

  // GLFW calls these from show_frame(), on this thread; none of them throws.
  glfwSetWindowSizeCallback(m_window,
                            [](GLFWwindow* window, int w, int h) { of(window).fit_camera(w, h); });
  glfwSetKeyCallback(m_window, [](GLFWwindow* window, int key, int, int action, int) {
    if (key == GLFW_KEY_ESCAPE && action == GLFW_PRESS) glfwSetWindowShouldClose(window, GLFW_TRUE);
  });
  glfwSetMouseButtonCallback(m_window, [](GLFWwindow* window, int button, int action, int) {
    ViewerWindow& self = of(window);
    if (button != GLFW_MOUSE_BUTTON_LEFT) return;
    if (action == GLFW_PRESS) self.m_drag.press(self.camera(), self.cursor());
    if (action == GLFW_RELEASE) self.m_drag.release();
  });
  glfwSetCursorPosCallback(m_window, [](GLFWwindow* window, double x, double y) {
    ViewerWindow& self = of(window);
    if (!self.m_drag.dragging()) return;
    self.m_drag.move(self.camera(), {x, y});
    self.target_moved();
  });
  glfwSetScrollCallback(m_window, [](GLFWwindow* window, double, double notches) {
    ViewerWindow& self = of(window);
    self.m_drag.scroll(self.camera(), notches);
    self.target_moved();
  });
}

ViewerWindow::~ViewerWindow() {
  glfwDestroyWindow(m_window);
  glfwTerminate();
}

ViewerWindow& ViewerWindow::of(GLFWwindow* window) noexcept {
  return *static_cast<ViewerWindow*>(glfwGetWindowUserPointer(window));
}

void ViewerWindow::fit_camera(int width, int height) {
  if (width < 1 || height < 1) return;  // minimized: keep the last camera
  const run::FrameOptions defaults;
  m_camera.emplace(m_framing.camera(defaults.view_direction, defaults.up, width, height));
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

void ViewerWindow::set_title(const std::string& title) noexcept {
  glfwSetWindowTitle(m_window, title.c_str());
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
