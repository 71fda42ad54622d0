#pragma once
// The two encodings of an MSH file behind one interface, so the MSH readers are written once.
// Section markers ("$Nodes") are text lines in both. Values are whitespace-separated tokens on
// rows (MshTextInput, errors at file:line) or untagged binary numbers (MshBinaryInput: size_t
// and double 8 bytes, int 4, errors at the byte offset where the value starts). Either input
// offers:
//   next_marker(token)  the first token of the next non-blank line; false at the end of data
//   begin_row(...)      text: moves to the next line, which holds one row; binary: nothing
//   end_row(what)       text: fails if the row holds more values; binary: nothing
//   size(), integer(), real(), skip_real()   one value each (size_t, int, double)
//   check_count_fits(count, bytes_each, what), and the least bytes a value takes
//   fail(message), fail_at_end(message)

#include <khz/reduced/errors.hpp>

#include "detail/byte_reader.hpp"
#include "detail/number_text.hpp"
#include "detail/text_scanner.hpp"

#include <cmath>
#include <cstdint>
#include <string>
#include <string_view>

namespace khz::reduced::detail {

/// An ASCII MSH file, read through the TextScanner that read its $MeshFormat line.
class MshTextInput {
 public:
  // A value and its separator take at least two bytes.
  static constexpr std::size_t size_bytes = 2;
  static constexpr std::size_t integer_bytes = 2;
  static constexpr std::size_t real_bytes = 2;

  explicit MshTextInput(TextScanner& scanner) : m_scanner(scanner) {}

  bool next_marker(std::string_view& token) {
    if (!m_scanner.next_content_line(no_comment)) return false;
    token = m_scanner.next_token();
    return true;
  }

  void begin_row(std::string_view expected) {
    m_scanner.require_content_line(no_comment, expected);
  }
  /// Moves to the row of `item` number `index` (0-based) of `count`.
  void begin_row(std::string_view item, std::int64_t index, std::int64_t count) {
    m_scanner.require_row(no_comment, item, index, count);
  }
  /// `what` names the row, e.g. "a node block header".
  void end_row(std::string_view what) {
    if (!m_scanner.line_exhausted()) {
      m_scanner.fail("unexpected " + quoted_token(m_scanner.next_token()) + " at the end of " +
                     std::string(what));
    }
  }

  std::int64_t size(std::string_view what, std::int64_t min, std::int64_t max) {
    return m_scanner.require_integer(what, min, max);
  }
  std::int64_t integer(std::string_view what, std::int64_t min, std::int64_t max) {
    return m_scanner.require_integer(what, min, max);
  }
  double real(std::string_view what) { return m_scanner.require_double(what); }
  /// Skips a double without parsing it (bounding boxes, which the readers do not use).
  void skip_real(std::string_view what) { m_scanner.require_token(what); }

  void check_count_fits(std::int64_t count, std::size_t min_bytes_each,
                        std::string_view what) const {
    detail::check_count_fits(m_scanner, count, min_bytes_each, what);
  }

  /// Fails at the current line.
  [[noreturn]] void fail(const std::string& message) const { m_scanner.fail(message); }
  /// Fails just past the last line: the file ended where `message` expected more.
  [[noreturn]] void fail_at_end(const std::string& message) const {
    throw ParseError::at_line(m_scanner.source(), m_scanner.line_number() + 1, message);
  }

  TextScanner& scanner() { return m_scanner; }

 private:
  TextScanner& m_scanner;
};

/// A binary MSH file (file-type 1, data size 8) from the byte after its $MeshFormat version line.
class MshBinaryInput {
 public:
  static constexpr std::size_t size_bytes = 8;
  static constexpr std::size_t integer_bytes = 4;
  static constexpr std::size_t real_bytes = 8;

  MshBinaryInput(std::string_view data, const std::string& source, std::size_t offset)
      : m_data(data), m_reader(data, source, offset), m_start(offset) {}

  /// Reads the int 1 that follows the version line; its bytes give the file's byte order.
  void read_byte_order() {
    m_start = m_reader.offset();
    const auto check = m_reader.read<std::uint32_t>(Endian::little, "the endianness check int");
    if (check == 0x01000000u) {
      m_endian = Endian::big;
    } else if (check != 1) {
      fail("endianness check reads " + std::to_string(check) + ", expected 1");
    }
  }

  /// A marker line starts after white space (the line break that ends binary data) and ends at
  /// a line break; binary data starts right after it.
  bool next_marker(std::string_view& token) {
    std::size_t start = m_reader.offset();
    while (start < m_data.size() && is_space(m_data[start])) ++start;
    if (start == m_data.size()) return false;
    const std::size_t end = m_data.find('\n', start);
    const std::size_t stop = end == std::string_view::npos ? m_data.size() : end;
    std::size_t token_end = start;
    while (token_end < stop && !is_space(m_data[token_end])) ++token_end;
    token = m_data.substr(start, token_end - start);
    m_start = start;
    const std::size_t next = end == std::string_view::npos ? m_data.size() : end + 1;
    m_reader.skip(next - m_reader.offset(), "a section marker");
    return true;
  }

  void begin_row(std::string_view) {}
  void begin_row(std::string_view, std::int64_t, std::int64_t) {}
  void end_row(std::string_view) {}

  std::int64_t size(std::string_view what, std::int64_t min, std::int64_t max) {
    m_start = m_reader.offset();
    const auto value = m_reader.read<std::uint64_t>(m_endian, what);
    if (value < static_cast<std::uint64_t>(min) || value > static_cast<std::uint64_t>(max)) {
      fail(outside_range(what, std::to_string(value), min, max));
    }
    return static_cast<std::int64_t>(value);
  }
  std::int64_t integer(std::string_view what, std::int64_t min, std::int64_t max) {
    m_start = m_reader.offset();
    const std::int64_t value = m_reader.read<std::int32_t>(m_endian, what);
    if (value < min || value > max) fail(outside_range(what, std::to_string(value), min, max));
    return value;
  }
  double real(std::string_view what) {
    m_start = m_reader.offset();
    const auto value = m_reader.read<double>(m_endian, what);
    if (!std::isfinite(value)) {
      fail("expected " + std::string(what) + " (a finite number), found " + number_text(value));
    }
    return value;
  }
  void skip_real(std::string_view what) {
    m_start = m_reader.offset();
    m_reader.skip(real_bytes, what);
  }

  void check_count_fits(std::int64_t count, std::size_t min_bytes_each,
                        std::string_view what) const {
    detail::check_count_fits(*this, count, min_bytes_each, what);
  }
  std::size_t remaining_bytes() const noexcept { return m_reader.remaining_bytes(); }

  /// Fails at the start of the last value or marker line read.
  [[noreturn]] void fail(const std::string& message) const {
    throw ParseError::at_byte(m_reader.source(), static_cast<std::int64_t>(m_start), message);
  }
  /// Fails at the end of the data.
  [[noreturn]] void fail_at_end(const std::string& message) const {
    throw ParseError::at_byte(m_reader.source(), static_cast<std::int64_t>(m_data.size()), message);
  }

 private:
  static bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n'; }

  std::string_view m_data;
  ByteReader m_reader;
  Endian m_endian = Endian::little;
  std::size_t m_start;  // offset of the last value or marker line read
};

}  // namespace khz::reduced::detail
