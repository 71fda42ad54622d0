#include "detail/file_bytes.hpp"

#include <khz/reduced/errors.hpp>

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <random>

namespace khz::reduced::detail {
namespace {

std::string reason() { return errno != 0 ? std::strerror(errno) : "unknown error"; }

/// Opens a new file next to `file` with a name no other writer uses: ".<name>.tmp-<pid>-<n>".
/// Returns the descriptor and sets `temporary` to its path.
int create_temporary(const std::filesystem::path& file, std::filesystem::path& temporary) {
  static std::atomic<unsigned> counter{std::random_device{}()};
  const std::filesystem::path directory =
      file.has_parent_path() ? file.parent_path() : std::filesystem::path(".");
  for (int attempt = 0; attempt < 100; ++attempt) {
    // Built by appending: GCC 12 at -O3 mistakes a chain of string + for overlapping memcpy
    // (-Wrestrict false positive).
    std::string name = ".";
    name.append(file.filename().string())
        .append(".tmp-")
        .append(std::to_string(::getpid()))
        .append("-")
        .append(std::to_string(counter++));
    temporary = directory / name;
    errno = 0;
    const int fd = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd >= 0 || errno != EEXIST) {
      if (fd < 0) {
        throw IoError(file.string() + ": cannot create a temporary file in " + directory.string() +
                      ": " + reason());
      }
      return fd;
    }
  }
  throw IoError(file.string() + ": cannot create a temporary file in " + directory.string() +
                ": every name tried exists");
}

/// Writes all of `bytes` to `fd`, retrying short writes and interruptions. False on failure.
bool write_all(int fd, std::string_view bytes) {
  while (!bytes.empty()) {
    errno = 0;
    const ::ssize_t written = ::write(fd, bytes.data(), bytes.size());
    if (written < 0) {
      if (errno == EINTR) continue;
      return false;
    }
    bytes.remove_prefix(static_cast<std::size_t>(written));
  }
  return true;
}

/// Flushes the directory entry of a rename to disk. Best effort: the rename has already
/// happened, and some file systems cannot sync directories.
void sync_directory(const std::filesystem::path& file) {
  const std::filesystem::path directory =
      file.has_parent_path() ? file.parent_path() : std::filesystem::path(".");
  const int fd = ::open(directory.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return;
  ::fsync(fd);
  ::close(fd);
}

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

void replace_file_bytes(const std::filesystem::path& file, std::string_view bytes) {
  replace_file_bytes(file, std::span<const std::string_view>(&bytes, 1));
}

void replace_file_bytes(const std::filesystem::path& file,
                        std::span<const std::string_view> pieces) {
  std::filesystem::path temporary;
  const int fd = create_temporary(file, temporary);
  const auto fail = [&](const std::string& what, int error) {
    std::error_code ignored;
    std::filesystem::remove(temporary, ignored);
    throw IoError(file.string() + ": " + what + ": " +
                  (error != 0 ? std::strerror(error) : "unknown error"));
  };
  if (!std::all_of(pieces.begin(), pieces.end(),
                   [&](std::string_view piece) { return write_all(fd, piece); })) {
    const int error = errno;
    ::close(fd);
    fail("write failed", error);
  }
  if (::fsync(fd) != 0) {
    const int error = errno;
    ::close(fd);
    fail("cannot flush to disk", error);
  }
  if (::close(fd) != 0) fail("write failed", errno);
  if (::rename(temporary.c_str(), file.c_str()) != 0) {
    fail("cannot rename " + temporary.filename().string() + " into place", errno);
  }
  sync_directory(file);
}

}  // namespace khz::reduced::detail
