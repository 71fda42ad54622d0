#pragma once
// The renderer's pixel type: an 8-bit-per-channel RGB colour.

#include <cstdint>

namespace khz::render {

/// An RGB colour, 8 bits per channel (0 = none, 255 = full), in sRGB as PNG viewers show it.
/// The renderer does no colour management: shading scales the channels and the bytes go to the
/// file as they are.
struct Color {
  std::uint8_t r = 0;
  std::uint8_t g = 0;
  std::uint8_t b = 0;

  friend bool operator==(const Color&, const Color&) = default;
};

}  // namespace khz::render
