#include "detail/text_scanner.hpp"

#include <charconv>
#include <cmath>
#include <utility>

namespace khz::reduced::detail {
namespace {

bool is_space(char c) noexcept {
  return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v';
}

std::string_view skip_space(std::string_view s) noexcept {
  std::size_t i = 0;
  while (i < s.size() && is_space(s[i])) ++i;
  return s.substr(i);
}

}  // namespace

TextScanner::TextScanner(std::string_view data, std::string source)
    : m_data(data), m_source(std::move(source)) {}

bool TextScanner::next_line() {
  if (m_next >= m_data.size()) {
    m_line = {};
    return false;
  }
  const std::size_t end = m_data.find('\n', m_next);
  const std::size_t stop = end == std::string_view::npos ? m_data.size() : end;
  m_line = m_data.substr(m_next, stop - m_next);
  if (!m_line.empty() && m_line.back() == '\r') m_line.remove_suffix(1);
  m_next = end == std::string_view::npos ? m_data.size() : end + 1;
  ++m_line_number;
  return true;
}

bool TextScanner::next_content_line(char comment) {
  while (next_line()) {
    const std::string_view content = skip_space(m_line);
    if (!content.empty() && content.front() != comment) return true;
  }
  return false;
}

void TextScanner::require_content_line(char comment, std::string_view expected) {
  if (!next_content_line(comment)) {
    throw ParseError::at_line(m_source, m_line_number + 1,
                              "file ends early: expected " + std::string(expected));
  }
}

void TextScanner::require_row(char comment, std::string_view item, std::int64_t index,
                              std::int64_t count) {
  if (next_content_line(comment)) return;
  throw ParseError::at_line(m_source, m_line_number + 1,
                            "file ends early: expected " + std::string(item) + " " +
                                std::to_string(index + 1) + " of " + std::to_string(count));
}

std::string_view TextScanner::next_token() {
  m_line = skip_space(m_line);
  std::size_t i = 0;
  while (i < m_line.size() && !is_space(m_line[i])) ++i;
  const std::string_view token = m_line.substr(0, i);
  m_line.remove_prefix(i);
  return token;
}

std::string_view TextScanner::require_token(std::string_view expected) {
  const std::string_view token = next_token();
  if (token.empty()) fail("expected " + std::string(expected) + ", found end of line");
  return token;
}

std::string_view TextScanner::rest_of_line() {
  m_line = skip_space(m_line);
  return m_line;
}

bool TextScanner::line_exhausted() { return skip_space(m_line).empty(); }

double TextScanner::require_double(std::string_view what) {
  const std::string_view token = require_token(what);
  double value = 0.0;
  if (!parse_double(token, value)) {
    fail("expected " + std::string(what) + " (a finite number), found " + quoted_token(token));
  }
  return value;
}

std::int64_t TextScanner::require_integer(std::string_view what, std::int64_t min,
                                          std::int64_t max) {
  const std::string_view token = require_token(what);
  std::int64_t value = 0;
  if (!parse_integer(token, value)) {
    fail("expected " + std::string(what) + " (an integer), found " + quoted_token(token));
  }
  if (value < min || value > max) {
    fail(outside_range(what, std::to_string(value), min, max));
  }
  return value;
}

void TextScanner::fail(const std::string& message) const {
  throw ParseError::at_line(m_source, m_line_number, message);
}

std::string quoted_token(std::string_view token) {
  constexpr std::size_t max_shown = 40;
  std::string shown(token.substr(0, max_shown));
  for (char& c : shown) {
    if (static_cast<unsigned char>(c) < 0x20 || static_cast<unsigned char>(c) >= 0x7f) c = '?';
  }
  return "'" + shown + (token.size() > max_shown ? "...'" : "'");
}

bool parse_double(std::string_view token, double& value) noexcept {
  if (!token.empty() && token.front() == '+') token.remove_prefix(1);
  const char* end = token.data() + token.size();
  const auto result = std::from_chars(token.data(), end, value);
  return result.ec == std::errc() && result.ptr == end && std::isfinite(value);
}

bool parse_integer(std::string_view token, std::int64_t& value) noexcept {
  if (!token.empty() && token.front() == '+') token.remove_prefix(1);
  const char* end = token.data() + token.size();
  const auto result = std::from_chars(token.data(), end, value);
  return result.ec == std::errc() && result.ptr == end;
}

std::string outside_range(std::string_view what, std::string_view value, std::int64_t min,
                          std::int64_t max) {
  return std::string(what) + " " + std::string(value) + " is outside [" + std::to_string(min) +
         ", " + std::to_string(max) + "]";
}

}  // namespace khz::reduced::detail
