#pragma once
// Number output shared by every writer: shortest round-trip text and byte-ordered binary.

#include "detail/byte_reader.hpp"

#include <algorithm>
#include <bit>
#include <charconv>
#include <cstring>
#include <string>

namespace khz::reduced::detail {

/// Appends the shortest text that reads back as exactly `value` (std::to_chars), so text
/// formats round-trip bit-exactly.
template <typename T>
void append_number(std::string& out, T value) {
  char buffer[32];  // the longest shortest-form double, "-2.2250738585072014e-308", has 24
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  out.append(buffer, static_cast<std::size_t>(result.ptr - buffer));
}

/// `value` as the shortest text that reads back exactly, for error messages.
template <typename T>
std::string number_text(T value) {
  std::string text;
  append_number(text, value);
  return text;
}

/// Appends `value`'s bytes in byte order `endian`.
template <typename T>
void append_binary(std::string& out, T value, Endian endian) {
  char bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));
  if ((endian == Endian::little) != (std::endian::native == std::endian::little)) {
    std::reverse(bytes, bytes + sizeof(T));
  }
  out.append(bytes, sizeof(T));
}

}  // namespace khz::reduced::detail
