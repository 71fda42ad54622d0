#pragma once
// An RGB image in memory: what the rasterizer draws into and what PNG files hold.

#include <khz/render/color.hpp>

#include <cassert>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace khz::render {

/// A width × height grid of RGB8 pixels. Pixel (x, y) is column x from the left and row y from
/// the top, as in PNG files. Copyable; equality compares size and every pixel.
class Image {
 public:
  /// Largest accepted width and height, in pixels: 16384² pixels is 805 MB of RGB, and every
  /// byte index stays within std::ptrdiff_t on any platform.
  static constexpr int max_size = 16384;

  /// An image filled with `fill`.
  /// @throws khz::reduced::Error naming the value if width or height is not in [1, max_size].
  Image(int width, int height, Color fill = {});

  int width() const noexcept { return m_width; }
  int height() const noexcept { return m_height; }

  /// The pixel at column x, row y. Requires 0 ≤ x < width() and 0 ≤ y < height() (asserted in
  /// debug builds).
  Color pixel(int x, int y) const noexcept {
    const std::uint8_t* p = &m_rgb[offset(x, y)];
    return {p[0], p[1], p[2]};
  }
  /// Sets the pixel at column x, row y; same preconditions as pixel().
  void set_pixel(int x, int y, Color color) noexcept {
    std::uint8_t* p = &m_rgb[offset(x, y)];
    p[0] = color.r;
    p[1] = color.g;
    p[2] = color.b;
  }
  /// Sets every pixel to `color`.
  void fill(Color color) noexcept;

  /// The pixels as bytes: rows top to bottom, each row left to right, three bytes (R, G, B) per
  /// pixel, no padding; 3 · width() · height() bytes in all.
  std::span<const std::uint8_t> bytes() const noexcept { return m_rgb; }
  std::span<std::uint8_t> bytes() noexcept { return m_rgb; }

  friend bool operator==(const Image&, const Image&) = default;

 private:
  std::size_t offset(int x, int y) const noexcept {
    assert(x >= 0 && x < m_width && y >= 0 && y < m_height);
    return 3 * (static_cast<std::size_t>(y) * static_cast<std::size_t>(m_width) +
                static_cast<std::size_t>(x));
  }

  int m_width;
  int m_height;
  std::vector<std::uint8_t> m_rgb;
};

}  // namespace khz::render
