#include "detail/file_bytes.hpp"

#include <khz/reduced/errors.hpp>

#include <cerrno>
#include <cstring>
#include <fstream>

namespace khz::reduced::detail {
namespace {

std::string reason() { return errno != 0 ? std::strerror(errno) : "unknown error"; }

}  // namespace

std::string read_file_bytes(const std::filesystem::path& file) {
  errno = 0;
  std::error_code ec;
  if (std::filesystem::is_directory(file, ec)) {
    throw IoError(file.string() + ": is a directory, expected a file");
  }
  std::ifstream in(file, std::ios::binary);
  if (!in) throw IoError(file.string() + ": cannot open for reading: " + reason());
  std::string bytes;
  in.seekg(0, std::ios::end);
  const std::streamoff size = in.tellg();
  if (size < 0) throw IoError(file.string() + ": cannot determine the file size");
  bytes.resize(static_cast<std::size_t>(size));
  in.seekg(0, std::ios::beg);
  in.read(bytes.data(), size);
  if (in.gcount() != size) throw IoError(file.string() + ": read failed: " + reason());
  return bytes;
}

void write_file_bytes(const std::filesystem::path& file, std::string_view bytes) {
  errno = 0;
  std::ofstream out(file, std::ios::binary | std::ios::trunc);
  if (!out) throw IoError(file.string() + ": cannot open for writing: " + reason());
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  out.flush();
  if (!out) throw IoError(file.string() + ": write failed: " + reason());
}

}  // namespace khz::reduced::detail
