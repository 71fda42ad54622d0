#pragma once
// Exceptions thrown by set-up code in libreduced (file I/O, mesh checks, precomputation).
// Real-time code never throws; it reports a status in its result instead.

#include <khz/reduced/export.hpp>

#include <cstdint>
#include <stdexcept>
#include <string>

namespace khz::reduced {

/// Base of every exception libreduced throws. Catch this to handle any Kilohertz set-up failure.
class KHZ_REDUCED_API Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A file could not be opened, read or written (missing, permissions, disk full).
class KHZ_REDUCED_API IoError : public Error {
 public:
  using Error::Error;
};

/// A file's content is malformed, truncated or inconsistent. what() reads
/// "<source>:<line>: <message>" for text formats and "<source>: byte <offset>: <message>" for
/// binary ones, so a person can jump straight to the problem.
class KHZ_REDUCED_API ParseError : public Error {
 public:
  /// Error at a 1-based line of a text file.
  static ParseError at_line(const std::string& source, std::int64_t line,
                            const std::string& message);
  /// Error at a 0-based byte offset of a binary file.
  static ParseError at_byte(const std::string& source, std::int64_t byte_offset,
                            const std::string& message);

  const std::string& source() const noexcept { return m_source; }
  /// 1-based line, or -1 when the error is located by byte offset.
  std::int64_t line() const noexcept { return m_line; }
  /// 0-based byte offset, or -1 when the error is located by line.
  std::int64_t byte_offset() const noexcept { return m_byte_offset; }
  /// The message without the location prefix.
  const std::string& message() const noexcept { return m_message; }

 private:
  ParseError(const std::string& what, std::string source, std::int64_t line,
             std::int64_t byte_offset, std::string message);

  std::string m_source;
  std::int64_t m_line;
  std::int64_t m_byte_offset;
  std::string m_message;
};

/// A mesh violates an invariant an operation needs (index out of range, non-finite coordinate,
/// inverted element, ...). element() names the offending element or vertex when there is one.
class KHZ_REDUCED_API MeshError : public Error {
 public:
  explicit MeshError(const std::string& message, std::int64_t element = -1);
  /// Index of the offending element (triangle, tetrahedron, ...) or -1.
  std::int64_t element() const noexcept { return m_element; }

 private:
  std::int64_t m_element;
};

/// A numerical procedure failed: a factorization met a singular or indefinite matrix, or a
/// Newton solve diverged or ran out of iterations. The message says which and with what residual;
/// the solver's state is left as it was before the failing call.
class KHZ_REDUCED_API SolverError : public Error {
 public:
  using Error::Error;
};

/// A long computation stopped because its ProgressCallback asked it to (returned false). Nothing
/// partial is returned; the inputs are unchanged.
class KHZ_REDUCED_API Cancelled : public Error {
 public:
  using Error::Error;
};

}  // namespace khz::reduced
