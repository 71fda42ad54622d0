#pragma once
// Checked binary container: the versioned, checksummed envelope of Kilohertz's own binary files
// (basis files and reduced models today; distance fields later).
//
// Layout, every number little-endian:
//
//   offset 0    8 bytes   magic, fixed per file type (e.g. "KHZBASIS")
//   offset 8    uint32    format version of that file type (1, 2, ...)
//   offset 12   uint64    length of the whole file in bytes, checksum included
//   offset 20   ...       payload: a sequence of the values below, as the file type defines
//   length − 8  uint64    XXH3-64 (seed 0) of bytes [0, length − 8)
//
// Payload values carry no type tags; the file type's documentation fixes their order.
//   u32, i32 .............. 4 bytes          u64, f64 ................ 8 bytes (f64: IEEE 754)
//   string ................ u64 byte count, then the bytes (UTF-8 by convention, no terminator)
//   doubles / ints ........ u64 count, then count f64 / i32
//   matrix ................ u64 rows, u64 cols, then rows·cols f64 in column-major order
//
// Reading checks, in this order, each failure a ParseError at the offending byte: the magic
// ("not a <description>"), the version (0, or newer than this build reads), the declared length
// against the file's size (truncation, trailing bytes), the checksum, and then, value by value,
// that every count fits in the bytes that remain before anything is allocated from it. The
// checksum catches accidental damage; it is no defence against a deliberately forged file, which
// the size checks keep from exhausting memory.

#include <khz/reduced/export.hpp>

#include <Eigen/Core>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace khz::reduced {

/// Identifies one file type in the container: its magic and the newest version this build
/// writes and reads. Each file type defines one as a constant (see basis_file.hpp).
struct ContainerFormat {
  /// Exactly 8 bytes, e.g. "KHZBASIS".
  std::string_view magic;
  /// What the file is, for messages: "Kilohertz basis file" gives "not a Kilohertz basis file".
  std::string_view description;
  /// Version written, and the newest version read (older ones are read too; the reader tells
  /// the caller which one it met).
  std::uint32_t version = 1;
};

/// Bytes before the payload: magic, version and length.
inline constexpr std::size_t container_header_bytes = 20;
/// Bytes after the payload: the checksum.
inline constexpr std::size_t container_checksum_bytes = 8;

/// Builds a container in memory, value by value, then writes it to a file in one step.
class KHZ_REDUCED_API ContainerWriter {
 public:
  /// Starts a container of `format` at format.version.
  /// @throws Error if format.magic is not 8 bytes or format.version is 0.
  explicit ContainerWriter(const ContainerFormat& format);

  /// Appends a 4-byte unsigned integer.
  void write_u32(std::uint32_t value);
  /// Appends an 8-byte unsigned integer (counts, sizes, hashes).
  void write_u64(std::uint64_t value);
  /// Appends a 4-byte signed integer.
  void write_i32(std::int32_t value);
  /// Appends an IEEE 754 double, bit for bit (NaN payloads and −0.0 included).
  void write_f64(double value);
  /// Appends a u64 byte count, then the bytes (any bytes; UTF-8 by convention).
  void write_string(std::string_view text);
  /// Appends a u64 count, then the values bit for bit.
  void write_doubles(std::span<const double> values);
  /// Appends a u64 count, then the values as int32.
  void write_ints(std::span<const int> values);
  /// Appends u64 rows, u64 cols, then the entries column by column (any Eigen block or map of
  /// doubles; strides are followed). Readers accept at most 2147483647 rows and columns.
  void write_matrix(const Eigen::Ref<const Eigen::MatrixXd>& matrix);

  /// The complete file: header, payload so far, checksum. The writer stays usable.
  std::string bytes() const;
  /// Writes bytes() to `file` atomically: into a temporary file in the same directory, flushed
  /// to disk and renamed over `file`, so a crash leaves the old file or the new one, never a
  /// part. @throws IoError naming `file` and the system's reason (no space, permissions, ...).
  void write_file(const std::filesystem::path& file) const;

 private:
  std::string m_bytes;  // header with the length still zero, then the payload
};

/// Reads a container: the constructor checks the envelope (magic, version, length, checksum),
/// then the read_* calls take the payload's values in order. Every failure is a ParseError
/// "<source>: byte <offset>: <message>" at the first byte of the offending field.
class KHZ_REDUCED_API ContainerReader {
 public:
  /// Checks `bytes` as a container of `format` named `source` in messages.
  /// @throws ParseError "not a <description> (...)" for a wrong magic (at byte 0), "file ends
  ///         early: ..." for a file cut short (at the end of the data present), "written by a
  ///         newer version N; this build reads up to M" (at byte 8), "... bytes after the end of
  ///         the file ..." for trailing data, "checksum mismatch: file is corrupted ..." (at the
  ///         checksum's offset).
  /// @throws Error if format.magic is not 8 bytes.
  ContainerReader(std::string bytes, std::string source, const ContainerFormat& format);

  /// Reads and checks the whole of `file` (its path is the source in messages).
  /// @throws IoError if the file cannot be read; ParseError as the constructor.
  static ContainerReader open(const std::filesystem::path& file, const ContainerFormat& format);

  /// The file's format version, 1 ≤ version() ≤ format.version.
  std::uint32_t version() const noexcept { return m_version; }
  /// Size of the whole file in bytes.
  std::size_t file_bytes() const noexcept { return m_bytes.size(); }
  /// The name messages use (the path for open()).
  const std::string& source() const noexcept { return m_source; }
  /// Byte offset of the next value.
  std::size_t offset() const noexcept { return m_offset; }
  /// Payload bytes not yet read (the checksum is not counted).
  std::size_t remaining_bytes() const noexcept { return m_end - m_offset; }
  /// Byte offset where the data of the last value read begins: the value itself for scalars,
  /// the first byte or item after the count for strings and arrays, the first entry for
  /// matrices. Item i of an int array is at value_offset() + 4·i.
  std::size_t value_offset() const noexcept { return m_value_offset; }

  // Each read_* takes the next value of its kind; `what` names it in messages ("file ends
  // early: expected <what> (8 bytes, 3 left)"). Each throws ParseError at the value's offset if
  // fewer bytes remain than it needs, and the length-prefixed ones at the count's offset if the
  // count exceeds what remains, before allocating anything.

  /// Reads a u32 written by write_u32().
  std::uint32_t read_u32(std::string_view what);
  /// Reads a u64 written by write_u64().
  std::uint64_t read_u64(std::string_view what);
  /// Reads an i32 written by write_i32().
  std::int32_t read_i32(std::string_view what);
  /// Reads a double written by write_f64(), bit for bit; it may be NaN or infinite.
  double read_f64(std::string_view what);
  /// Reads a string written by write_string(); its bytes are not checked (UTF-8 or not).
  std::string read_string(std::string_view what);
  /// Reads an array written by write_doubles(); values may be NaN or infinite.
  std::vector<double> read_doubles(std::string_view what);
  /// Reads an array written by write_ints(); the caller checks the range of the values.
  std::vector<int> read_ints(std::string_view what);
  /// Reads a matrix written by write_matrix(); entries may be NaN or infinite.
  /// @throws ParseError (at the row count) also if a dimension exceeds 2147483647.
  Eigen::MatrixXd read_matrix(std::string_view what);

  /// Checks that the whole payload has been read.
  /// @throws ParseError "N unread bytes after <what>" at the first unread byte.
  void finish(std::string_view what) const;

  /// Throws ParseError at `offset` of this file with `message`.
  [[noreturn]] void fail_at(std::size_t offset, const std::string& message) const;

 private:
  /// Checks `count` bytes remain for `what`, sets value_offset() and returns the read position.
  std::size_t take(std::size_t count, std::string_view what);
  /// Reads an item count and checks that count items of `item_bytes` fit.
  std::size_t read_count(std::size_t item_bytes, std::string_view what);

  std::string m_bytes;
  std::string m_source;
  std::uint32_t m_version = 0;
  std::size_t m_offset = 0;
  std::size_t m_end = 0;  // end of the payload (start of the checksum)
  std::size_t m_value_offset = 0;
};

}  // namespace khz::reduced
