#include <khz/scene/cache_directory.hpp>

#include <cstdlib>

namespace khz::scene {
namespace {

/// The variable's value as a path if it is set to an absolute path; empty otherwise.
std::filesystem::path absolute_variable(const char* name) {
  const char* value = std::getenv(name);
  if (value == nullptr) return {};
  const std::filesystem::path path(value);
  return path.is_absolute() ? path : std::filesystem::path();
}

}  // namespace

std::filesystem::path default_cache_directory() {
  if (const std::filesystem::path xdg = absolute_variable("XDG_CACHE_HOME"); !xdg.empty()) {
    return xdg / "kilohertz";
  }
  if (const std::filesystem::path home = absolute_variable("HOME"); !home.empty()) {
    return home / ".cache" / "kilohertz";
  }
  return {};
}

}  // namespace khz::scene
