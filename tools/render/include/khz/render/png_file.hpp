#pragma once
// PNG files of images (8-bit RGB), through libpng.

#include <khz/render/image.hpp>

#include <filesystem>

namespace khz::render {

/// Writes `image` to `file` as an 8-bit RGB PNG marked sRGB (no alpha), replacing the file if
/// it exists.
/// @throws khz::reduced::IoError naming `file` if it cannot be opened or written (the file may
///         then be left truncated); khz::reduced::Error naming it if libpng fails to encode.
void write_png(const Image& image, const std::filesystem::path& file);

/// Reads a PNG file of any colour type and bit depth as 8-bit RGB: grey is replicated,
/// palettes are expanded, 16-bit channels are reduced and an alpha channel is composited onto
/// black. An 8-bit RGB file written by write_png() reads back pixel for pixel.
/// @throws khz::reduced::IoError naming `file` if it cannot be opened or read;
///         khz::reduced::Error naming it with libpng's reason if it is not a valid PNG file or
///         is larger than Image::max_size on a side.
Image read_png(const std::filesystem::path& file);

}  // namespace khz::render
