#include <khz/reduced/errors.hpp>
#include <khz/reduced/io/binary_container.hpp>

#include "detail/file_bytes.hpp"
#include "detail/number_text.hpp"

#include <xxhash.h>

#include <algorithm>
#include <bit>
#include <cstdio>
#include <cstring>
#include <limits>
#include <memory>
#include <new>
#include <string>
#include <type_traits>
#include <utility>

namespace khz::reduced {
namespace {

static_assert(sizeof(int) == 4, "ints are stored as int32");
static_assert(std::numeric_limits<double>::is_iec559, "doubles are stored as IEEE 754 binary64");

constexpr std::size_t magic_bytes = 8;
constexpr std::size_t version_offset = 8;
constexpr std::size_t length_offset = 12;
/// Largest matrix dimension read; keeps rows·cols and Eigen's indices far from overflow.
constexpr std::uint64_t max_dimension = std::numeric_limits<std::int32_t>::max();

void check_format(const ContainerFormat& format) {
  if (format.magic.size() != magic_bytes) {
    throw Error("container format '" + std::string(format.description) + "': the magic must be " +
                std::to_string(magic_bytes) + " bytes, not " + std::to_string(format.magic.size()));
  }
  if (format.version == 0) {
    throw Error("container format '" + std::string(format.description) + "': versions start at 1");
  }
}

/// Reverses the bytes of a value on big-endian hosts, so files are little-endian everywhere.
template <typename T>
T to_little_endian(T value) {
  if constexpr (std::endian::native == std::endian::big) {
    unsigned char bytes[sizeof(T)];
    std::memcpy(bytes, &value, sizeof(T));
    for (std::size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(bytes[i], bytes[sizeof(T) - 1 - i]);
    std::memcpy(&value, bytes, sizeof(T));
  }
  return value;
}

template <typename T>
void append(std::string& out, T value) {
  static_assert(std::is_arithmetic_v<T>);
  detail::append_binary(out, value, detail::Endian::little);
}

template <typename T>
void append_array(std::string& out, const T* values, std::size_t count) {
  if constexpr (std::endian::native == std::endian::little) {
    out.append(reinterpret_cast<const char*>(values), count * sizeof(T));
  } else {
    for (std::size_t i = 0; i < count; ++i) append(out, values[i]);
  }
}

template <typename T>
T load(const std::string& bytes, std::size_t offset) {
  T value;
  std::memcpy(&value, bytes.data() + offset, sizeof(T));
  return to_little_endian(value);
}

template <typename T>
void load_array(const std::string& bytes, std::size_t offset, T* values, std::size_t count) {
  if constexpr (std::endian::native == std::endian::little) {
    if (count > 0) std::memcpy(values, bytes.data() + offset, count * sizeof(T));
  } else {
    for (std::size_t i = 0; i < count; ++i) values[i] = load<T>(bytes, offset + i * sizeof(T));
  }
}

std::uint64_t checksum(const char* data, std::size_t size) { return XXH3_64bits(data, size); }

std::string hex(std::uint64_t value) {
  char text[19];
  std::snprintf(text, sizeof(text), "0x%016llx", static_cast<unsigned long long>(value));
  return text;
}

/// Printable form of a magic for messages: ASCII kept, other bytes as \xNN.
std::string printable(std::string_view bytes) {
  std::string text;
  for (const char c : bytes) {
    const auto byte = static_cast<unsigned char>(c);
    if (byte >= 0x20 && byte < 0x7f && c != '"' && c != '\\') {
      text += c;
    } else {
      char escaped[5];
      std::snprintf(escaped, sizeof(escaped), "\\x%02x", byte);
      text += escaped;
    }
  }
  return text;
}

/// What frames a container's bytes (header with the length still zero, then the payload): the
/// header with the file's length filled in, and the trailing checksum of that header and the
/// payload — so that the payload, often hundreds of MB, need not be copied to be written.
struct Framing {
  std::string header;
  std::string trailer;
};

Framing framing(const std::string& bytes) {
  Framing frame{bytes.substr(0, container_header_bytes), {}};
  const std::uint64_t length =
      to_little_endian(static_cast<std::uint64_t>(bytes.size() + container_checksum_bytes));
  std::memcpy(frame.header.data() + length_offset, &length, sizeof(length));
  const std::unique_ptr<XXH3_state_t, decltype(&XXH3_freeState)> state(XXH3_createState(),
                                                                       &XXH3_freeState);
  if (!state) throw std::bad_alloc();
  XXH3_64bits_reset(state.get());
  XXH3_64bits_update(state.get(), frame.header.data(), frame.header.size());
  XXH3_64bits_update(state.get(), bytes.data() + frame.header.size(),
                     bytes.size() - frame.header.size());
  append(frame.trailer, static_cast<std::uint64_t>(XXH3_64bits_digest(state.get())));
  return frame;
}

}  // namespace

// ---- ContainerWriter ------------------------------------------------------------------------

ContainerWriter::ContainerWriter(const ContainerFormat& format) {
  check_format(format);
  m_bytes.append(format.magic);
  append(m_bytes, format.version);
  append(m_bytes, std::uint64_t{0});  // the length, filled in by bytes()
}

void ContainerWriter::write_u32(std::uint32_t value) { append(m_bytes, value); }
void ContainerWriter::write_u64(std::uint64_t value) { append(m_bytes, value); }
void ContainerWriter::write_i32(std::int32_t value) { append(m_bytes, value); }
void ContainerWriter::write_f64(double value) { append(m_bytes, value); }

void ContainerWriter::write_string(std::string_view text) {
  append(m_bytes, static_cast<std::uint64_t>(text.size()));
  m_bytes.append(text);
}

void ContainerWriter::write_doubles(std::span<const double> values) {
  append(m_bytes, static_cast<std::uint64_t>(values.size()));
  append_array(m_bytes, values.data(), values.size());
}

void ContainerWriter::write_ints(std::span<const int> values) {
  append(m_bytes, static_cast<std::uint64_t>(values.size()));
  append_array(m_bytes, values.data(), values.size());
}

void ContainerWriter::write_matrix(const Eigen::Ref<const Eigen::MatrixXd>& matrix) {
  append(m_bytes, static_cast<std::uint64_t>(matrix.rows()));
  append(m_bytes, static_cast<std::uint64_t>(matrix.cols()));
  m_bytes.reserve(m_bytes.size() + static_cast<std::size_t>(matrix.size()) * sizeof(double));
  for (Eigen::Index c = 0; c < matrix.cols(); ++c) {
    append_array(m_bytes, matrix.col(c).data(), static_cast<std::size_t>(matrix.rows()));
  }
}

std::string ContainerWriter::bytes() const {
  const Framing frame = framing(m_bytes);
  std::string out;
  out.reserve(m_bytes.size() + frame.trailer.size());
  out += frame.header;
  out.append(m_bytes, frame.header.size());
  out += frame.trailer;
  return out;
}

void ContainerWriter::write_file(const std::filesystem::path& file) const {
  const Framing frame = framing(m_bytes);
  const std::string_view pieces[] = {
      frame.header, std::string_view(m_bytes).substr(frame.header.size()), frame.trailer};
  detail::replace_file_bytes(file, pieces);
}

// ---- ContainerReader ------------------------------------------------------------------------

ContainerReader::ContainerReader(std::string bytes, std::string source,
                                 const ContainerFormat& format)
    : m_bytes(std::move(bytes)), m_source(std::move(source)) {
  check_format(format);
  const std::size_t size = m_bytes.size();
  const std::string_view head(m_bytes.data(), std::min(size, magic_bytes));
  if (head != format.magic.substr(0, head.size())) {
    fail_at(0, "not a " + std::string(format.description) + " (the file starts with \"" +
                   printable(head) + "\", expected \"" + printable(format.magic) + "\")");
  }
  m_end = size;
  m_offset = 0;
  take(magic_bytes, "the magic \"" + printable(format.magic) + "\"");
  m_version = read_u32("the format version");
  if (m_version == 0) fail_at(version_offset, "invalid format version 0");
  if (m_version > format.version) {
    fail_at(version_offset, "written by a newer version " + std::to_string(m_version) +
                                "; this build reads up to " + std::to_string(format.version));
  }
  const std::uint64_t length = read_u64("the file length");
  const std::uint64_t minimum = container_header_bytes + container_checksum_bytes;
  if (length < minimum) {
    fail_at(length_offset, "the header declares a file length of " + std::to_string(length) +
                               " bytes, less than the " + std::to_string(minimum) +
                               " of an empty container");
  }
  if (length > size) {
    fail_at(size, "file ends early: the header declares " + std::to_string(length) +
                      " bytes, the file has " + std::to_string(size) + " (truncated?)");
  }
  if (length < size) {
    fail_at(length, std::to_string(size - length) + " bytes after the end of the file (the " +
                        "header declares " + std::to_string(length) + " bytes)");
  }
  m_end = size - container_checksum_bytes;
  const std::uint64_t stored = load<std::uint64_t>(m_bytes, m_end);
  const std::uint64_t computed = checksum(m_bytes.data(), m_end);
  if (stored != computed) {
    fail_at(m_end, "checksum mismatch: file is corrupted (stored " + hex(stored) + ", computed " +
                       hex(computed) + ")");
  }
  m_value_offset = m_offset;
}

ContainerReader ContainerReader::open(const std::filesystem::path& file,
                                      const ContainerFormat& format) {
  return ContainerReader(detail::read_file_bytes(file), file.string(), format);
}

std::size_t ContainerReader::take(std::size_t count, std::string_view what) {
  if (count > remaining_bytes()) {
    fail_at(m_offset, "file ends early: expected " + std::string(what) + " (" +
                          std::to_string(count) + " bytes, " + std::to_string(remaining_bytes()) +
                          " left)");
  }
  m_value_offset = m_offset;
  m_offset += count;
  return m_value_offset;
}

std::size_t ContainerReader::read_count(std::size_t item_bytes, std::string_view what) {
  const std::size_t at = m_offset;
  const std::uint64_t count = read_u64("the length of " + std::string(what));
  if (count > remaining_bytes() / item_bytes) {
    const std::string items = item_bytes == 1 ? std::to_string(count) + " bytes"
                                              : std::to_string(count) + " items of " +
                                                    std::to_string(item_bytes) + " bytes";
    fail_at(at, std::string(what) + ": " + items + " do not fit in the " +
                    std::to_string(remaining_bytes()) + " bytes that remain");
  }
  m_value_offset = m_offset;
  return static_cast<std::size_t>(count);
}

std::uint32_t ContainerReader::read_u32(std::string_view what) {
  return load<std::uint32_t>(m_bytes, take(4, what));
}

std::uint64_t ContainerReader::read_u64(std::string_view what) {
  return load<std::uint64_t>(m_bytes, take(8, what));
}

std::int32_t ContainerReader::read_i32(std::string_view what) {
  return load<std::int32_t>(m_bytes, take(4, what));
}

double ContainerReader::read_f64(std::string_view what) {
  return load<double>(m_bytes, take(8, what));
}

std::string ContainerReader::read_string(std::string_view what) {
  const std::size_t length = read_count(1, what);
  std::string text = m_bytes.substr(m_offset, length);
  m_offset += length;
  return text;
}

std::vector<double> ContainerReader::read_doubles(std::string_view what) {
  const std::size_t count = read_count(sizeof(double), what);
  std::vector<double> values(count);
  load_array(m_bytes, m_offset, values.data(), count);
  m_offset += count * sizeof(double);
  return values;
}

std::vector<int> ContainerReader::read_ints(std::string_view what) {
  const std::size_t count = read_count(sizeof(int), what);
  std::vector<int> values(count);
  load_array(m_bytes, m_offset, values.data(), count);
  m_offset += count * sizeof(int);
  return values;
}

Eigen::MatrixXd ContainerReader::read_matrix(std::string_view what) {
  const std::size_t at = m_offset;
  const std::uint64_t rows = read_u64("the row count of " + std::string(what));
  const std::uint64_t cols = read_u64("the column count of " + std::string(what));
  const std::string shape = std::to_string(rows) + "×" + std::to_string(cols);
  if (rows > max_dimension || cols > max_dimension) {
    fail_at(at, std::string(what) + ": " + shape + " exceeds the dimension limit of " +
                    std::to_string(max_dimension));
  }
  // rows, cols < 2^31, so rows·cols < 2^62 cannot overflow.
  if (rows * cols > remaining_bytes() / sizeof(double)) {
    fail_at(at, std::string(what) + ": " + shape + " entries of 8 bytes do not fit in the " +
                    std::to_string(remaining_bytes()) + " bytes that remain");
  }
  Eigen::MatrixXd matrix(static_cast<Eigen::Index>(rows), static_cast<Eigen::Index>(cols));
  m_value_offset = m_offset;
  load_array(m_bytes, m_offset, matrix.data(), static_cast<std::size_t>(rows * cols));
  m_offset += static_cast<std::size_t>(rows * cols) * sizeof(double);
  return matrix;
}

void ContainerReader::finish(std::string_view what) const {
  if (remaining_bytes() != 0) {
    fail_at(m_offset,
            std::to_string(remaining_bytes()) + " unread bytes after " + std::string(what));
  }
}

void ContainerReader::fail_at(std::size_t offset, const std::string& message) const {
  throw ParseError::at_byte(m_source, static_cast<std::int64_t>(offset), message);
}

}  // namespace khz::reduced
