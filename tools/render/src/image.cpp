#include <khz/render/image.hpp>

#include <khz/reduced/errors.hpp>

#include <string>

namespace khz::render {
namespace {

int checked_size(int value, const char* name) {
  if (value < 1 || value > Image::max_size) {
    throw reduced::Error(std::string("image ") + name + " " + std::to_string(value) +
                         " is not in [1, " + std::to_string(Image::max_size) + "]");
  }
  return value;
}

}  // namespace

Image::Image(int width, int height, Color fill)
    : m_width(checked_size(width, "width")), m_height(checked_size(height, "height")) {
  m_rgb.resize(3 * static_cast<std::size_t>(m_width) * static_cast<std::size_t>(m_height));
  this->fill(fill);
}

void Image::fill(Color color) noexcept {
  for (std::size_t i = 0; i < m_rgb.size(); i += 3) {
    m_rgb[i] = color.r;
    m_rgb[i + 1] = color.g;
    m_rgb[i + 2] = color.b;
  }
}

}  // namespace khz::render
