#pragma once
// Text over the scene (OpenGL, fixed function): the overlay's status and help lines.

#include <span>
#include <string>
#include <vector>

namespace khz::viewer {

/// Draws lines of ASCII text in the window's corners, each block on a pale panel so it reads
/// over any surface: `status` from the top-left corner down, `help` from the bottom-left corner
/// up. The glyphs are stb_easy_font's, scaled so that about 32 lines of 80 characters fit the
/// framebuffer (never below the font's own size).
class OverlayView {
 public:
  OverlayView();

  /// Draws over what the current OpenGL context's framebuffer (`width` × `height` pixels)
  /// holds; leaves depth testing and lighting off, as it found them after SceneView::draw().
  void draw(std::span<const std::string> status, std::span<const std::string> help, int width,
            int height);

 private:
  /// One block of lines with its top-left corner at (x, y) (font units, y down).
  void draw_block(std::span<const std::string> lines, float x, float y);

  std::vector<char> m_vertices;  // stb_easy_font's quads of one line, reused
  std::string m_line;            // a mutable copy of the line: stb_easy_font takes char*
};

}  // namespace khz::viewer
