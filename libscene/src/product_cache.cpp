#include <khz/scene/product_cache.hpp>

#include <khz/reduced/errors.hpp>

#include <unistd.h>
#include <algorithm>
#include <cctype>

namespace khz::scene {

ProductCache::ProductCache(std::filesystem::path directory) : m_directory(std::move(directory)) {
  std::error_code error;
  std::filesystem::create_directories(m_directory, error);
  if (error || !std::filesystem::is_directory(m_directory)) {
    throw reduced::IoError("product cache: cannot create the directory " + m_directory.string() +
                           (error ? " (" + error.message() + ")" : ""));
  }
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
  // The process id keeps two preparations of the same scene from writing one temporary file.
  return target.string() + ".partial-" + std::to_string(::getpid());
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
