#include "file_replacement.hpp"

#include <khz/reduced/errors.hpp>

#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <string>
#include <system_error>
#include <vector>

namespace khz::series::detail {
namespace {

/// Removes the temporary file unless released: on an exception from `write` as on a failure.
class TemporaryFile {
 public:
  explicit TemporaryFile(std::filesystem::path path) : m_path(std::move(path)) {}
  TemporaryFile(const TemporaryFile&) = delete;
  TemporaryFile& operator=(const TemporaryFile&) = delete;
  ~TemporaryFile() {
    if (m_owned) {
      std::error_code ignored;
      std::filesystem::remove(m_path, ignored);
    }
  }
  const std::filesystem::path& path() const noexcept { return m_path; }
  void release() noexcept { m_owned = false; }

 private:
  std::filesystem::path m_path;
  bool m_owned = true;
};

/// A name no other writer uses at the same time: the process id keeps processes apart, the
/// counter threads (and successive files) of this one.
std::filesystem::path temporary_path(const std::filesystem::path& file) {
  static std::atomic<unsigned long> counter{0};
  std::string name = ".";
  name.append(file.filename().string())
      .append(".partial-")
      .append(std::to_string(::getpid()))
      .append("-")
      .append(std::to_string(counter.fetch_add(1)));
  return file.parent_path() / name;
}

}  // namespace

void replace_file(const std::filesystem::path& file,
                  const std::function<void(std::ostream& out)>& write) {
  TemporaryFile temporary(temporary_path(file));
  // Callers read errno before building `what`, which may allocate and change it.
  const auto fail = [&](int error_number, const std::string& what) {
    throw reduced::IoError(file.string() + ": " + what + ": " +
                           (error_number != 0 ? std::strerror(error_number) : "unknown error"));
  };
  errno = 0;
  {
    std::vector<char> buffer(std::size_t{1} << 20);
    std::ofstream out;
    out.rdbuf()->pubsetbuf(buffer.data(), static_cast<std::streamsize>(buffer.size()));
    out.open(temporary.path(), std::ios::binary | std::ios::trunc);
    if (!out) {
      const int reason = errno;
      fail(reason, "cannot create the temporary file " + temporary.path().string());
    }
    write(out);
    out.close();
    if (!out) {
      const int reason = errno;
      fail(reason, "write failed");
    }
  }
  std::error_code error;
  std::filesystem::rename(temporary.path(), file, error);
  if (error) {
    fail(error.value(), "cannot rename " + temporary.path().filename().string() + " into place");
  }
  temporary.release();
}

}  // namespace khz::series::detail
