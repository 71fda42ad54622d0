#include "overlay_view.hpp"

#include <GL/gl.h>

// Text as quads in legacy OpenGL from one public-domain header (Debian's libstb-dev): no font
// file, texture or loader to ship, and nothing to set up beyond the GL context the scene already
// uses. FreeType with a glyph texture would look better but needs far more code; GLUT's bitmap
// fonts would bring in a second window-system library. Its ASCII-only glyphs are why the
// overlay's text (overlay_text.hpp) is ASCII.
#include <stb_easy_font.h>

#include <algorithm>
#include <cmath>

namespace khz::viewer {
namespace {

/// stb_easy_font's line pitch and margins (font units: its pixels at scale 1).
constexpr float line_pitch = 12.0f;
constexpr float margin = 6.0f;
/// stb_easy_font's average use per character (bytes), from its documentation, with room.
constexpr std::size_t bytes_per_character = 300;

}  // namespace

OverlayView::OverlayView() : m_vertices(bytes_per_character * 200) {}

void OverlayView::draw(std::span<const std::string> status, std::span<const std::string> help,
                       int width, int height) {
  // About 32 lines of 80 characters (6 font units each, on average) fit the framebuffer; in
  // half steps, so that the glyphs' strokes stay even.
  const float fit = std::min(static_cast<float>(height) / (32.0f * line_pitch),
                             static_cast<float>(width) / (80.0f * 6.0f));
  const float scale = std::max(1.0f, std::floor(2.0f * fit) / 2.0f);
  glViewport(0, 0, width, height);
  glMatrixMode(GL_PROJECTION);
  glLoadIdentity();
  // Font units, y down from the top-left corner, as stb_easy_font writes its quads.
  glOrtho(0.0, width / scale, height / scale, 0.0, -1.0, 1.0);
  glMatrixMode(GL_MODELVIEW);
  glLoadIdentity();
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_LIGHTING);
  glEnable(GL_BLEND);
  glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
  draw_block(status, margin, margin);
  const float help_height = line_pitch * static_cast<float>(help.size());
  draw_block(help, margin, static_cast<float>(height) / scale - margin - help_height);
  glDisable(GL_BLEND);
}

void OverlayView::draw_block(std::span<const std::string> lines, float x, float y) {
  if (lines.empty()) return;
  float widest = 0.0f;
  for (const std::string& line : lines) {
    m_line = line;
    widest = std::max(widest, static_cast<float>(stb_easy_font_width(m_line.data())));
  }
  const float pad = 3.0f;
  glColor4f(1.0f, 1.0f, 1.0f, 0.75f);
  glRectf(x - pad, y - pad, x + widest + pad, y + line_pitch * static_cast<float>(lines.size()));

  glColor4f(0.1f, 0.1f, 0.1f, 1.0f);
  glEnableClientState(GL_VERTEX_ARRAY);
  for (std::size_t i = 0; i < lines.size(); ++i) {
    m_line = lines[i];
    m_vertices.resize(std::max(m_vertices.size(), bytes_per_character * (m_line.size() + 1)));
    const int quads =
        stb_easy_font_print(x, y + line_pitch * static_cast<float>(i), m_line.data(), nullptr,
                            m_vertices.data(), static_cast<int>(m_vertices.size()));
    // Each vertex: x, y, z as floats and a 4-byte colour (16 bytes); only x and y are read.
    glVertexPointer(2, GL_FLOAT, 16, m_vertices.data());
    glDrawArrays(GL_QUADS, 0, 4 * quads);
  }
  glDisableClientState(GL_VERTEX_ARRAY);
}

}  // namespace khz::viewer
