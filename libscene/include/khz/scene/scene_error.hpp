#pragma once
// The error every scene-file problem is reported with: the file, where in it, what was expected
// and what was found.

#include <khz/reduced/errors.hpp>
#include <khz/scene/export.hpp>

#include <string>

namespace khz::scene {

/// A scene file is malformed or inconsistent. A Kilohertz Error, so `catch (reduced::Error&)`
/// handles it with every other set-up failure. what() reads
///   "<source>: <key path>: <message>"       e.g. "scene.json: objects[1].model.basis.r:
///                                            expected an integer ≥ 1, got -3"
///   "<source>: <message>"                    when the whole file is concerned (empty key path)
///   "<source>:<line>:<column>: <message>"    for JSON syntax errors (as nlohmann/json counts them)
class KHZ_SCENE_API SceneError : public reduced::Error {
 public:
  /// An error at a key. @param key_path e.g. "objects[1].model.basis.r"; empty for the file.
  static SceneError at_key(const std::string& source, const std::string& key_path,
                           const std::string& message);
  /// A JSON syntax error at a 1-based line and a column.
  static SceneError at_position(const std::string& source, int line, int column,
                                const std::string& message);

  /// The scene file as it was named to the reader (or the source name given to parse_scene()).
  const std::string& source() const noexcept { return m_source; }
  /// The offending key's JSON path ("objects[1].model.basis.r"), empty for syntax errors and
  /// errors about the whole file.
  const std::string& key_path() const noexcept { return m_key_path; }
  /// 1-based line of a syntax error, 0 otherwise.
  int line() const noexcept { return m_line; }
  /// Column of a syntax error as nlohmann/json reports it, 0 otherwise.
  int column() const noexcept { return m_column; }
  /// The message without the location prefix: "expected an integer ≥ 1, got -3".
  const std::string& message() const noexcept { return m_message; }

 private:
  SceneError(const std::string& what, std::string source, std::string key_path, int line,
             int column, std::string message);

  std::string m_source;
  std::string m_key_path;
  int m_line = 0;
  int m_column = 0;
  std::string m_message;
};

}  // namespace khz::scene
