#include <khz/scene/prepare_error.hpp>

#include <utility>

namespace khz::scene {

PrepareError::PrepareError(std::string object, PrepareStep step, std::string cause)
    : reduced::Error("object \"" + object + "\": " + std::string(step_name(step)) + ": " + cause),
      m_object(std::move(object)),
      m_step(step),
      m_cause(std::move(cause)) {}

}  // namespace khz::scene
