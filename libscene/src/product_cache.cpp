#include <khz/scene/product_cache.hpp>

#include <khz/reduced/errors.hpp>

#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <csignal>
#include <string_view>

namespace {

/// What a temporary file's name carries after the product's: the host and the process writing
/// it, so that processes sharing a cache (on one host or several) never write the same file,
/// and a file left by a process that died can be told from one still being written.
const std::string_view partial_marker = ".partial-";

std::string this_host() {
  char name[256] = {};
  if (::gethostname(name, sizeof name - 1) != 0) return "host";
  std::string host = name;
  std::replace(host.begin(), host.end(), '-', '_');  // '-' separates host and process id
  return host;
}

/// Removes the temporary files in `directory` that a process of this host left when it died
/// (killed, out of memory, a crashed rank of an MPI job): a temporary of a live process is
/// being written and stays.
void remove_abandoned_temporaries(const std::filesystem::path& directory) {
  const std::string prefix = std::string(partial_marker) + this_host() + "-";
  std::error_code error;
  for (const auto& entry : std::filesystem::directory_iterator(directory, error)) {
    const std::string name = entry.path().filename().string();
    const std::size_t at = name.rfind(prefix);
    if (at == std::string::npos) continue;
    const std::string pid_text = name.substr(at + prefix.size());
    if (pid_text.empty() || !std::all_of(pid_text.begin(), pid_text.end(),
                                         [](unsigned char c) { return std::isdigit(c); })) {
      continue;
    }
    const pid_t pid = static_cast<pid_t>(std::stol(pid_text));
    if (::kill(pid, 0) == 0 || errno != ESRCH) continue;  // alive, or not ours to ask about
    std::error_code ignored;
    std::filesystem::remove(entry.path(), ignored);
  }
}

}  // namespace

namespace khz::scene {

ProductCache::ProductCache(std::filesystem::path directory) : m_directory(std::move(directory)) {
  std::error_code error;
  std::filesystem::create_directories(m_directory, error);
  if (error || !std::filesystem::is_directory(m_directory)) {
    throw reduced::IoError("product cache: cannot create the directory " + m_directory.string() +
                           (error ? " (" + error.message() + ")" : ""));
  }
  remove_abandoned_temporaries(m_directory);
}

std::filesystem::path ProductCache::file(const std::string& name, const std::string& key,
                                         const std::string& extension) const {
  std::string safe = name;
  std::replace_if(
      safe.begin(), safe.end(),
      [](unsigned char c) { return !(std::isalnum(c) || c == '-' || c == '_'); }, '_');
  return m_directory / (safe + "-" + key + "." + extension);
}

int ProductCache::computed_count() const noexcept {
  return static_cast<int>(std::count_if(m_records.begin(), m_records.end(),
                                        [](const Record& r) { return r.computed; }));
}

std::filesystem::path ProductCache::temporary_file(const std::filesystem::path& target) const {
  static const std::string host = this_host();
  return target.string() + std::string(partial_marker) + host + "-" + std::to_string(::getpid());
}

void ProductCache::commit(const std::filesystem::path& temporary,
                          const std::filesystem::path& target) {
  std::error_code error;
  std::filesystem::rename(temporary, target, error);
  if (error) {
    throw reduced::IoError("product cache: cannot move " + temporary.string() + " to " +
                           target.string() + " (" + error.message() + ")");
  }
}

void ProductCache::record(const std::string& name, const std::filesystem::path& file, bool computed,
                          std::chrono::steady_clock::time_point start, std::string damaged) {
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  m_records.push_back({name, file, computed, seconds, std::move(damaged)});
}

}  // namespace khz::scene
