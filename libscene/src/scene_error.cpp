#include <khz/scene/scene_error.hpp>

#include <utility>

namespace khz::scene {

SceneError SceneError::at_key(const std::string& source, const std::string& key_path,
                              const std::string& message) {
  const std::string what =
      key_path.empty() ? source + ": " + message : source + ": " + key_path + ": " + message;
  return SceneError(what, source, key_path, 0, 0, message);
}

SceneError SceneError::at_position(const std::string& source, int line, int column,
                                   const std::string& message) {
  const std::string what =
      source + ":" + std::to_string(line) + ":" + std::to_string(column) + ": " + message;
  return SceneError(what, source, {}, line, column, message);
}

SceneError::SceneError(const std::string& what, std::string source, std::string key_path, int line,
                       int column, std::string message)
    : Error(what),
      m_source(std::move(source)),
      m_key_path(std::move(key_path)),
      m_line(line),
      m_column(column),
      m_message(std::move(message)) {}

}  // namespace khz::scene
