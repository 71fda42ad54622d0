#include <khz/reduced/errors.hpp>
#include <khz/reduced/io/basis_export.hpp>
#include <khz/reduced/version.hpp>
#include <khz/test/fixtures.hpp>

#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <limits>
#include <stdexcept>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

namespace khz::reduced {
namespace {

/// 4 vertices, r = 3, with values that show any transposition or reordering.
Basis small_basis() {
  Basis basis;
  basis.vectors.resize(12, 3);
  for (Eigen::Index c = 0; c < 3; ++c) {
    for (Eigen::Index r = 0; r < 12; ++r) basis.vectors(r, c) = 100.0 * c + r + 0.5;
  }
  basis.vectors(5, 1) = -0.0;
  basis.vectors(6, 2) = std::numeric_limits<double>::denorm_min();
  basis.fixed_vertices = {1, 3};
  basis.recipe = "linear modes: k=3";
  return basis;
}

/// Little-endian value at `offset` of `bytes` (the test host is little-endian).
template <typename T>
T at(const std::string& bytes, std::size_t offset) {
  if (offset + sizeof(T) > bytes.size()) throw std::out_of_range("read past the end");
  T value;
  std::memcpy(&value, bytes.data() + offset, sizeof(T));
  return value;
}

/// The column-major bytes of `matrix`.
std::string column_bytes(const Eigen::MatrixXd& matrix) {
  return {reinterpret_cast<const char*>(matrix.data()),
          static_cast<std::size_t>(matrix.size()) * sizeof(double)};
}

// ---- NumPy ----------------------------------------------------------------------------------

TEST(BasisExport, NpyHasTheVersion1HeaderAndColumnMajorData) {
  const Basis basis = small_basis();
  const std::filesystem::path file = test::scratch_file("U.npy");
  write_basis_npy(file, basis);
  const std::string bytes = test::read_bytes(file);
  EXPECT_EQ(bytes, format_basis_npy(basis));

  ASSERT_GE(bytes.size(), 10u);
  EXPECT_EQ(bytes.substr(0, 6), "\x93NUMPY");
  EXPECT_EQ(bytes[6], 1);  // major version
  EXPECT_EQ(bytes[7], 0);  // minor version
  const std::size_t header_length = at<std::uint16_t>(bytes, 8);
  const std::size_t data_start = 10 + header_length;
  EXPECT_EQ(data_start % 64, 0u);  // NumPy's alignment
  const std::string header = bytes.substr(10, header_length);
  const std::string dictionary = "{'descr': '<f8', 'fortran_order': True, 'shape': (12, 3), }";
  EXPECT_EQ(header.substr(0, dictionary.size()), dictionary);
  EXPECT_EQ(header.back(), '\n');
  EXPECT_EQ(header.find_first_not_of(' ', dictionary.size()), header.size() - 1);  // padding

  ASSERT_EQ(bytes.size(), data_start + 12 * 3 * 8);
  EXPECT_EQ(bytes.substr(data_start), column_bytes(basis.vectors));
  EXPECT_EQ(at<double>(bytes, data_start + 8 * (12 * 2 + 7)), basis.vectors(7, 2));
}

TEST(BasisExport, NpyWritesAnEmptyBasis) {
  Basis basis;
  basis.vectors.resize(6, 0);
  const std::string bytes = format_basis_npy(basis);
  EXPECT_NE(bytes.find("'shape': (6, 0), }"), std::string::npos);
  EXPECT_EQ(bytes.size(), 128u);  // a 10-byte preamble and the 59-byte dictionary, padded
}

// ---- MAT-file Level 5 -----------------------------------------------------------------------

/// One miMATRIX variable as read back.
struct MatVariable {
  std::uint32_t array_class = 0;
  std::uint32_t flags = 0;
  std::vector<std::int32_t> dimensions;
  std::string name;
  std::uint32_t data_type = 0;
  std::string data;
};

/// Reads the data element at `offset` (the full, 8-byte tag form), checks its padding and
/// returns its type and data; `offset` moves past the padding.
std::pair<std::uint32_t, std::string> read_element(const std::string& bytes, std::size_t& offset) {
  const auto type = at<std::uint32_t>(bytes, offset);
  const auto size = at<std::uint32_t>(bytes, offset + 4);
  if (offset + 8 + size > bytes.size()) throw std::out_of_range("element past the end");
  std::string data = bytes.substr(offset + 8, size);
  offset += 8 + size;
  while (offset % 8 != 0) {
    if (bytes.at(offset++) != '\0') throw std::runtime_error("non-zero padding");
  }
  return {type, data};
}

/// Parses a whole Level 5 MAT-file: the header, then miMATRIX elements up to the end.
std::vector<MatVariable> parse_mat(const std::string& bytes) {
  if (bytes.size() < 128) throw std::runtime_error("no 128-byte header");
  if (at<std::uint16_t>(bytes, 124) != 0x0100) throw std::runtime_error("version is not 0x0100");
  if (bytes.substr(126, 2) != "IM") throw std::runtime_error("not little-endian 'IM'");
  std::vector<MatVariable> variables;
  std::size_t offset = 128;
  while (offset < bytes.size()) {
    const auto [type, body] = read_element(bytes, offset);
    if (type != 14) throw std::runtime_error("not an miMATRIX element");
    MatVariable variable;
    std::size_t inner = 0;
    const auto [flags_type, flags] = read_element(body, inner);
    if (flags_type != 6 || flags.size() != 8) throw std::runtime_error("bad array flags");
    variable.flags = at<std::uint32_t>(flags, 0);
    variable.array_class = variable.flags & 0xff;
    const auto [dimensions_type, dimensions] = read_element(body, inner);
    if (dimensions_type != 5) throw std::runtime_error("dimensions are not miINT32");
    for (std::size_t d = 0; d < dimensions.size(); d += 4) {
      variable.dimensions.push_back(at<std::int32_t>(dimensions, d));
    }
    const auto [name_type, name] = read_element(body, inner);
    if (name_type != 1) throw std::runtime_error("name is not miINT8");
    variable.name = name;
    std::tie(variable.data_type, variable.data) = read_element(body, inner);
    if (inner != body.size()) throw std::runtime_error("extra sub-elements");
    variables.push_back(std::move(variable));
  }
  return variables;
}

TEST(BasisExport, MatHasTheLevel5HeaderAndThreeVariables) {
  const Basis basis = small_basis();
  const std::filesystem::path file = test::scratch_file("basis.mat");
  write_basis_mat(file, basis);
  const std::string bytes = test::read_bytes(file);
  EXPECT_EQ(bytes, format_basis_mat(basis));

  EXPECT_EQ(bytes.substr(0, 19), "MATLAB 5.0 MAT-file");
  EXPECT_NE(bytes.substr(0, 116).find(library_version()), std::string::npos);
  EXPECT_EQ(bytes.substr(116, 8), std::string(8, '\0'));  // no subsystem data
  EXPECT_EQ(bytes.size() % 8, 0u);

  const std::vector<MatVariable> variables = parse_mat(bytes);
  ASSERT_EQ(variables.size(), 3u);

  const MatVariable& u = variables[0];
  EXPECT_EQ(u.name, "U");
  EXPECT_EQ(u.flags, 6u);  // mxDOUBLE_CLASS; not complex, global or logical
  EXPECT_EQ(u.dimensions, (std::vector<std::int32_t>{12, 3}));
  EXPECT_EQ(u.data_type, 9u);  // miDOUBLE
  EXPECT_EQ(u.data, column_bytes(basis.vectors));

  const MatVariable& fixed = variables[1];
  EXPECT_EQ(fixed.name, "fixed_vertices");
  EXPECT_EQ(fixed.array_class, 12u);  // mxINT32_CLASS
  EXPECT_EQ(fixed.dimensions, (std::vector<std::int32_t>{2, 1}));
  EXPECT_EQ(fixed.data_type, 5u);  // miINT32
  ASSERT_EQ(fixed.data.size(), 8u);
  EXPECT_EQ(at<std::int32_t>(fixed.data, 0), 1);  // zero-based, as in Kilohertz
  EXPECT_EQ(at<std::int32_t>(fixed.data, 4), 3);

  const MatVariable& recipe = variables[2];
  EXPECT_EQ(recipe.name, "recipe");
  EXPECT_EQ(recipe.array_class, 4u);  // mxCHAR_CLASS
  EXPECT_EQ(recipe.dimensions, (std::vector<std::int32_t>{1, 17}));
  EXPECT_EQ(recipe.data_type, 16u);  // miUTF8
  EXPECT_EQ(recipe.data, "linear modes: k=3");
}

TEST(BasisExport, MatCountsCharactersNotBytesAndReplacesInvalidUtf8) {
  Basis basis;
  basis.vectors.resize(3, 1);
  basis.vectors.setZero();
  // "µ" is 2 bytes, "≈" 3; a lone continuation byte, a truncated sequence, an overlong "/",
  // a surrogate and a character outside the BMP (4 bytes) are each replaced byte by byte.
  basis.recipe = "µ≈1 \x80|\xe2\x89|\xc0\xaf|\xed\xa0\x80|\xf0\x9f\x98\x80";
  const std::vector<MatVariable> variables = parse_mat(format_basis_mat(basis));
  ASSERT_EQ(variables.size(), 3u);
  const MatVariable& recipe = variables[2];
  EXPECT_EQ(recipe.data, "µ≈1 ?|??|??|???|????");
  EXPECT_EQ(recipe.dimensions, (std::vector<std::int32_t>{1, 20}));
}

TEST(BasisExport, MatWritesEmptyVariables) {
  Basis basis;
  basis.vectors.resize(6, 0);
  const std::vector<MatVariable> variables = parse_mat(format_basis_mat(basis));
  ASSERT_EQ(variables.size(), 3u);
  EXPECT_EQ(variables[0].dimensions, (std::vector<std::int32_t>{6, 0}));
  EXPECT_TRUE(variables[0].data.empty());
  EXPECT_EQ(variables[1].dimensions, (std::vector<std::int32_t>{0, 1}));
  EXPECT_EQ(variables[2].dimensions, (std::vector<std::int32_t>{0, 0}));
}

TEST(BasisExport, WriteFailuresNameThePath) {
  const std::filesystem::path file = test::scratch_file("absent") / "basis.mat";
  EXPECT_TRUE(test::throws_with_message<IoError>([&] { write_basis_mat(file, small_basis()); },
                                                 file.string() + ": cannot create"));
  EXPECT_TRUE(test::throws_with_message<IoError>([&] { write_basis_npy(file, small_basis()); },
                                                 file.string() + ": cannot create"));
}

}  // namespace
}  // namespace khz::reduced
