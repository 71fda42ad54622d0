#pragma once
// Bounds-checked reading of binary mesh formats with byte-offset error locations.

#include <khz/reduced/errors.hpp>

#include <bit>
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>
#include <type_traits>

namespace khz::reduced::detail {

/// Byte order of a binary file.
enum class Endian { little, big };

/// Reads fixed-size values from a byte buffer. Reading past the end throws ParseError
/// ("file ends early") naming the source and the offset of the failed read.
class ByteReader {
 public:
  ByteReader(std::string_view data, std::string source, std::size_t offset = 0)
      : m_data(data), m_source(std::move(source)), m_offset(offset) {}

  /// Reads one arithmetic value of type T stored with byte order `endian`.
  template <typename T>
  T read(Endian endian, std::string_view what) {
    static_assert(std::is_arithmetic_v<T>);
    require(sizeof(T), what);
    unsigned char bytes[sizeof(T)];
    std::memcpy(bytes, m_data.data() + m_offset, sizeof(T));
    const bool native_little = std::endian::native == std::endian::little;
    if ((endian == Endian::little) != native_little) {
      for (std::size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(bytes[i], bytes[sizeof(T) - 1 - i]);
    }
    T value;
    std::memcpy(&value, bytes, sizeof(T));
    m_offset += sizeof(T);
    return value;
  }

  /// Skips `count` bytes.
  void skip(std::size_t count, std::string_view what) {
    require(count, what);
    m_offset += count;
  }

  /// Throws unless `count` more bytes are available.
  void require(std::size_t count, std::string_view what) const {
    if (count > remaining_bytes()) {
      fail("file ends early: expected " + std::string(what) + " (" + std::to_string(count) +
           " bytes, " + std::to_string(remaining_bytes()) + " left)");
    }
  }

  std::size_t offset() const noexcept { return m_offset; }
  std::size_t remaining_bytes() const noexcept { return m_data.size() - m_offset; }
  const std::string& source() const noexcept { return m_source; }

  /// Throws ParseError at the current offset.
  [[noreturn]] void fail(const std::string& message) const {
    throw ParseError::at_byte(m_source, static_cast<std::int64_t>(m_offset), message);
  }

 private:
  std::string_view m_data;
  std::string m_source;
  std::size_t m_offset;
};

}  // namespace khz::reduced::detail
