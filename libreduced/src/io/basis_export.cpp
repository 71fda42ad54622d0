#include <khz/reduced/errors.hpp>
#include <khz/reduced/io/basis_export.hpp>
#include <khz/reduced/version.hpp>

#include "detail/file_bytes.hpp"
#include "detail/number_text.hpp"

#include <bit>
#include <cstdint>
#include <limits>
#include <string>
#include <string_view>
#include <utility>

namespace khz::reduced {
namespace {

using detail::append_binary;
using detail::Endian;

template <typename T>
void append_le(std::string& out, T value) {
  append_binary(out, value, Endian::little);
}

/// Appends `count` values little-endian: one copy on little-endian hosts.
template <typename T>
void append_le_array(std::string& out, const T* values, std::size_t count) {
  if constexpr (std::endian::native == std::endian::little) {
    out.append(reinterpret_cast<const char*>(values), count * sizeof(T));
  } else {
    for (std::size_t i = 0; i < count; ++i) append_le(out, values[i]);
  }
}

void append_columns(std::string& out, const Eigen::MatrixXd& matrix) {
  append_le_array(out, matrix.data(), static_cast<std::size_t>(matrix.size()));
}

// ---- NumPy --------------------------------------------------------------------------------

/// NumPy aligns the data of the files it writes to 64 bytes; we do the same.
constexpr std::size_t npy_alignment = 64;

// ---- MAT-file Level 5 ---------------------------------------------------------------------
// "MATLAB MAT-File Format" (The MathWorks, R2013b+), chapter 1: a 128-byte header, then data
// elements, each an 8-byte tag (u32 type, u32 byte count) and data padded to 8 bytes.

enum MatDataType : std::uint32_t {
  mi_int8 = 1,
  mi_int32 = 5,
  mi_uint32 = 6,
  mi_double = 9,
  mi_matrix = 14,
  mi_utf8 = 16,
};

enum MatClass : std::uint32_t {
  mx_char_class = 4,
  mx_double_class = 6,
  mx_int32_class = 12,
};

constexpr std::uint64_t mat_max_bytes = std::numeric_limits<std::uint32_t>::max();
constexpr std::int64_t mat_max_dimension = std::numeric_limits<std::int32_t>::max();

void pad_to_8(std::string& out) { out.append((8 - out.size() % 8) % 8, '\0'); }

/// A data element: tag, `data`, zero padding to a multiple of 8 bytes.
void append_element(std::string& out, std::uint32_t type, std::string_view data) {
  append_le(out, type);
  append_le(out, static_cast<std::uint32_t>(data.size()));
  out.append(data);
  pad_to_8(out);
}

/// An miMATRIX element holding one real, non-sparse array: flags, dimensions, name, data.
void append_matrix(std::string& out, std::string_view name, MatClass array_class, std::int64_t rows,
                   std::int64_t cols, MatDataType data_type, std::string_view data) {
  if (rows > mat_max_dimension || cols > mat_max_dimension) {
    throw Error("MAT-file export: variable '" + std::string(name) + "' is " + std::to_string(rows) +
                "×" + std::to_string(cols) + "; Level 5 dimensions are limited to " +
                std::to_string(mat_max_dimension));
  }
  std::string flags;
  append_le(flags, static_cast<std::uint32_t>(array_class));  // no complex/global/logical bits
  append_le(flags, std::uint32_t{0});                         // nzmax, for sparse arrays only
  std::string dimensions;
  append_le(dimensions, static_cast<std::int32_t>(rows));
  append_le(dimensions, static_cast<std::int32_t>(cols));

  std::string body;
  append_element(body, mi_uint32, flags);
  append_element(body, mi_int32, dimensions);
  append_element(body, mi_int8, name);
  if (body.size() + 8 + data.size() + 8 > mat_max_bytes) {
    throw Error("MAT-file export: variable '" + std::string(name) + "' needs " +
                std::to_string(data.size()) +
                " bytes, more than a Level 5 variable can hold; use the NumPy export");
  }
  append_element(body, data_type, data);
  append_le(out, static_cast<std::uint32_t>(mi_matrix));
  append_le(out, static_cast<std::uint32_t>(body.size()));
  out += body;
}

/// `text` with every byte that does not start or continue a valid UTF-8 sequence of a
/// Basic Multilingual Plane character replaced by '?', and its number of characters. Within the
/// BMP, MATLAB's UTF-16 characters and Unicode code points (scipy's count) agree.
std::pair<std::string, std::int64_t> bmp_utf8(std::string_view text) {
  std::string out;
  std::int64_t characters = 0;
  std::size_t i = 0;
  while (i < text.size()) {
    const auto byte = [&](std::size_t k) { return static_cast<unsigned char>(text[k]); };
    const unsigned char lead = byte(i);
    std::size_t length = 0;
    unsigned char low = 0x80;   // range of the second byte, narrowed to exclude overlong
    unsigned char high = 0xbf;  // encodings and UTF-16 surrogates
    if (lead < 0x80) {
      length = 1;
    } else if (lead >= 0xc2 && lead <= 0xdf) {
      length = 2;
    } else if (lead >= 0xe0 && lead <= 0xef) {
      length = 3;
      if (lead == 0xe0) low = 0xa0;
      if (lead == 0xed) high = 0x9f;
    }
    bool valid = length > 0 && i + length <= text.size();
    for (std::size_t k = 1; valid && k < length; ++k) {
      const unsigned char next = byte(i + k);
      valid = k == 1 ? next >= low && next <= high : next >= 0x80 && next <= 0xbf;
    }
    if (valid) {
      out.append(text.substr(i, length));
      i += length;
    } else {
      out += '?';
      ++i;
    }
    ++characters;
  }
  return {out, characters};
}

}  // namespace

std::string format_basis_npy(const Basis& basis) {
  const std::string dictionary = "{'descr': '<f8', 'fortran_order': True, 'shape': (" +
                                 std::to_string(basis.vectors.rows()) + ", " +
                                 std::to_string(basis.vectors.cols()) + "), }";
  constexpr std::size_t preamble = 10;               // magic (6), version (2), header length (2)
  std::size_t header_bytes = dictionary.size() + 1;  // + the terminating newline
  header_bytes += (npy_alignment - (preamble + header_bytes) % npy_alignment) % npy_alignment;

  std::string out("\x93NUMPY\x01\x00", 8);
  append_le(out, static_cast<std::uint16_t>(header_bytes));
  out += dictionary;
  out.append(header_bytes - dictionary.size() - 1, ' ');
  out += '\n';
  out.reserve(out.size() + static_cast<std::size_t>(basis.vectors.size()) * sizeof(double));
  append_columns(out, basis.vectors);
  return out;
}

void write_basis_npy(const std::filesystem::path& file, const Basis& basis) {
  detail::replace_file_bytes(file, format_basis_npy(basis));
}

std::string format_basis_mat(const Basis& basis) {
  std::string out = "MATLAB 5.0 MAT-file, written by Kilohertz ";
  out += library_version();
  out += " (khz::reduced::write_basis_mat)";
  out.resize(116, ' ');                   // descriptive text, padded with spaces
  out.append(8, '\0');                    // subsystem data offset: none
  append_le(out, std::uint16_t{0x0100});  // version
  out += "IM";  // endian indicator: 'M','I' as a 16-bit value, little-endian

  std::string data;
  data.reserve(static_cast<std::size_t>(basis.vectors.size()) * sizeof(double));
  append_columns(data, basis.vectors);
  append_matrix(out, "U", mx_double_class, basis.vectors.rows(), basis.vectors.cols(), mi_double,
                data);

  data.clear();
  append_le_array(data, basis.fixed_vertices.data(), basis.fixed_vertices.size());
  append_matrix(out, "fixed_vertices", mx_int32_class,
                static_cast<std::int64_t>(basis.fixed_vertices.size()), 1, mi_int32, data);

  const auto [recipe, characters] = bmp_utf8(basis.recipe);
  append_matrix(out, "recipe", mx_char_class, characters == 0 ? 0 : 1, characters, mi_utf8, recipe);
  return out;
}

void write_basis_mat(const std::filesystem::path& file, const Basis& basis) {
  detail::replace_file_bytes(file, format_basis_mat(basis));
}

}  // namespace khz::reduced
