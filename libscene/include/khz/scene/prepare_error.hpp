#pragma once
// The error a failed scene preparation is reported with: which object, which step, and why.

#include <khz/reduced/errors.hpp>
#include <khz/scene/export.hpp>
#include <khz/scene/prepared_scene.hpp>

#include <string>

namespace khz::scene {

/// Preparing an object failed. A Kilohertz Error, so `catch (reduced::Error&)` handles it with
/// every other set-up failure. what() reads
///   object "<object>": <step>: <cause>     e.g. object "dino": distance_field: cannot read ...
/// prepare_scene() throws it with std::throw_with_nested(), so the original exception (an
/// IoError, ParseError, MeshError, SolverError or Error) can be rethrown with
/// std::rethrow_if_nested() when its type matters.
class KHZ_SCENE_API PrepareError : public reduced::Error {
 public:
  PrepareError(std::string object, PrepareStep step, std::string cause);

  /// The object's name.
  const std::string& object() const noexcept { return m_object; }
  /// The step that failed (for a missing or unreadable mesh: the first step that needed it).
  PrepareStep step() const noexcept { return m_step; }
  /// The original message, without the object and step.
  const std::string& cause() const noexcept { return m_cause; }

 private:
  std::string m_object;
  PrepareStep m_step;
  std::string m_cause;
};

}  // namespace khz::scene
