// `khz info` for the files khz writes for other programs: PNG images (read back through
// khz_render), and ParaView and NumPy/MATLAB exports, which khz has no reader for.
#include "describe_files.hpp"

#include <khz/render/png_file.hpp>

#include <filesystem>
#include <iostream>

namespace khz::tool {

void describe_png_file(const std::string& file) {
  const render::Image image = render::read_png(file);
  info_line("kind") << "PNG image\n";
  info_line("width") << image.width() << " pixels\n";
  info_line("height") << image.height() << " pixels\n";
  describe_file_size(std::filesystem::file_size(file));
}

void describe_unread_file(const std::string& file, std::string_view what) {
  info_line("kind") << what << "\n";
  info_line("contents") << "not read: khz writes this format but has no reader for it\n";
  describe_file_size(std::filesystem::file_size(file));
}

}  // namespace khz::tool
