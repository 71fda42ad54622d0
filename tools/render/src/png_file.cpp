#include <khz/render/png_file.hpp>

#include <khz/reduced/errors.hpp>

#include <png.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

// libpng's simplified API (png_image_*) reports errors in the png_image struct instead of
// longjmp-ing out of the library, which would skip C++ destructors.

namespace khz::render {
namespace {

std::string reason() { return errno != 0 ? std::strerror(errno) : "unknown error"; }

std::string png_message(const png_image& png) {
  return png.message[0] != '\0' ? png.message : "unknown libpng error";
}

/// Frees libpng's read state on every path out of read_png().
struct PngImageGuard {
  png_image& png;
  ~PngImageGuard() { png_image_free(&png); }
};

}  // namespace

void write_png(const Image& image, const std::filesystem::path& file) {
  png_image png;
  std::memset(&png, 0, sizeof(png));
  png.version = PNG_IMAGE_VERSION;
  png.width = static_cast<png_uint_32>(image.width());
  png.height = static_cast<png_uint_32>(image.height());
  png.format = PNG_FORMAT_RGB;

  // Encode in memory first, so a libpng failure never leaves a half-written file behind.
  png_alloc_size_t size = 0;
  if (png_image_write_to_memory(&png, nullptr, &size, 0, image.bytes().data(), 0, nullptr) == 0) {
    throw reduced::Error(file.string() + ": cannot encode PNG: " + png_message(png));
  }
  std::vector<unsigned char> encoded(size);
  if (png_image_write_to_memory(&png, encoded.data(), &size, 0, image.bytes().data(), 0, nullptr) ==
      0) {
    throw reduced::Error(file.string() + ": cannot encode PNG: " + png_message(png));
  }

  errno = 0;
  std::ofstream out(file, std::ios::binary | std::ios::trunc);
  if (!out) throw reduced::IoError(file.string() + ": cannot open for writing: " + reason());
  out.write(reinterpret_cast<const char*>(encoded.data()), static_cast<std::streamsize>(size));
  out.flush();
  if (!out) throw reduced::IoError(file.string() + ": write failed: " + reason());
}

Image read_png(const std::filesystem::path& file) {
  errno = 0;
  std::error_code ec;
  if (std::filesystem::is_directory(file, ec)) {
    throw reduced::IoError(file.string() + ": is a directory, expected a PNG file");
  }
  std::ifstream in(file, std::ios::binary);
  if (!in) throw reduced::IoError(file.string() + ": cannot open for reading: " + reason());
  const std::vector<unsigned char> bytes((std::istreambuf_iterator<char>(in)),
                                         std::istreambuf_iterator<char>());
  if (in.bad()) throw reduced::IoError(file.string() + ": read failed: " + reason());

  png_image png;
  std::memset(&png, 0, sizeof(png));
  png.version = PNG_IMAGE_VERSION;
  const PngImageGuard guard{png};
  if (png_image_begin_read_from_memory(&png, bytes.data(), bytes.size()) == 0) {
    throw reduced::Error(file.string() + ": not a readable PNG file: " + png_message(png));
  }
  if (png.width > static_cast<png_uint_32>(Image::max_size) ||
      png.height > static_cast<png_uint_32>(Image::max_size)) {
    throw reduced::Error(file.string() + ": PNG image of " + std::to_string(png.width) + "×" +
                         std::to_string(png.height) + " pixels is larger than " +
                         std::to_string(Image::max_size) + " on a side");
  }
  png.format = PNG_FORMAT_RGB;
  Image image(static_cast<int>(png.width), static_cast<int>(png.height));
  const png_color black{0, 0, 0};  // what an alpha channel is composited onto
  if (png_image_finish_read(&png, &black, image.bytes().data(), 0, nullptr) == 0) {
    throw reduced::Error(file.string() + ": not a readable PNG file: " + png_message(png));
  }
  return image;
}

}  // namespace khz::render
