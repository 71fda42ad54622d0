#include <khz/reduced/errors.hpp>

#include <utility>

namespace khz::reduced {

ParseError::ParseError(const std::string& what, std::string source, std::int64_t line,
                       std::int64_t byte_offset, std::string message)
    : Error(what),
      m_source(std::move(source)),
      m_line(line),
      m_byte_offset(byte_offset),
      m_message(std::move(message)) {}

ParseError ParseError::at_line(const std::string& source, std::int64_t line,
                               const std::string& message) {
  return ParseError(source + ":" + std::to_string(line) + ": " + message, source, line, -1,
                    message);
}

ParseError ParseError::at_byte(const std::string& source, std::int64_t byte_offset,
                               const std::string& message) {
  return ParseError(source + ": byte " + std::to_string(byte_offset) + ": " + message, source, -1,
                    byte_offset, message);
}

MeshError::MeshError(const std::string& message, std::int64_t element)
    : Error(message), m_element(element) {}

}  // namespace khz::reduced
