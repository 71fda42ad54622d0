#include <khz/reduced/errors.hpp>
#include <khz/reduced/io/basis_file.hpp>
#include <khz/reduced/io/mesh_fingerprint.hpp>

#include "detail/number_text.hpp"
#include "io/basis_payload.hpp"

#include <cmath>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace khz::reduced {
namespace detail {
namespace {

/// The first problem with a fixed-vertex list for n vertices, and its index, if any.
std::optional<std::pair<std::size_t, std::string>> fixed_vertex_problem(
    const std::vector<int>& fixed, Eigen::Index n) {
  for (std::size_t i = 0; i < fixed.size(); ++i) {
    if (fixed[i] < 0 || fixed[i] >= n) {
      return std::pair{i, "fixed vertex " + std::to_string(fixed[i]) + " (entry " +
                              std::to_string(i) + ") is out of range [0, " + std::to_string(n) +
                              ")"};
    }
    if (i > 0 && fixed[i] <= fixed[i - 1]) {
      return std::pair{i, "fixed vertices must be sorted and distinct: entry " + std::to_string(i) +
                              " is " + std::to_string(fixed[i]) + " after " +
                              std::to_string(fixed[i - 1])};
    }
  }
  return std::nullopt;
}

/// The index of the first non-finite value, if any.
std::optional<std::size_t> first_non_finite(std::span<const double> values) {
  for (std::size_t k = 0; k < values.size(); ++k) {
    if (!std::isfinite(values[k])) return k;
  }
  return std::nullopt;
}

std::span<const double> entries(const Eigen::MatrixXd& matrix) {
  return {matrix.data(), static_cast<std::size_t>(matrix.size())};
}

/// "<name>(i, j) = <value> is not finite" for entry k (column-major) of `matrix`.
std::string entry_text(std::string_view name, const Eigen::MatrixXd& matrix, std::size_t k) {
  const auto rows = static_cast<std::size_t>(matrix.rows());
  std::string text(name);
  text.append("(").append(std::to_string(k % rows)).append(", ");
  text.append(std::to_string(k / rows)).append(") = ").append(number_text(matrix.data()[k]));
  return text.append(" is not finite");
}

std::string shape_text(Eigen::Index rows, Eigen::Index cols) {
  return std::to_string(rows) + "×" + std::to_string(cols);
}

}  // namespace

void check_basis_writable(const std::filesystem::path& file, std::string_view noun,
                          const Basis& basis, const VolumeMesh& mesh, Eigen::Index max_size) {
  const auto fail = [&](const std::string& message) {
    std::string text = file.string();
    text.append(": cannot write ").append(noun).append(": ").append(message);
    throw Error(text);
  };
  const Eigen::Index n = mesh.num_vertices();
  if (n > max_basis_vertices) {
    fail("the mesh has " + std::to_string(n) + " vertices, more than the " +
         std::to_string(max_basis_vertices) + " a basis file can hold");
  }
  if (basis.size() > max_size) {
    fail("r = " + std::to_string(basis.size()) + " exceeds the limit of " +
         std::to_string(max_size));
  }
  if (basis.vectors.rows() != 3 * n) {
    fail("U has " + std::to_string(basis.vectors.rows()) + " rows, expected 3·" +
         std::to_string(n) + " = " + std::to_string(3 * n) + " (3 per mesh vertex)");
  }
  if (const auto k = first_non_finite(entries(basis.vectors))) {
    fail(entry_text("U", basis.vectors, *k));
  }
  if (const auto problem = fixed_vertex_problem(basis.fixed_vertices, n)) fail(problem->second);
}

void write_basis_payload(ContainerWriter& writer, const Basis& basis, const VolumeMesh& mesh) {
  writer.write_u64(mesh_fingerprint(mesh));
  writer.write_u64(static_cast<std::uint64_t>(mesh.num_vertices()));
  writer.write_u64(static_cast<std::uint64_t>(basis.size()));
  writer.write_string(basis.recipe);
  writer.write_ints(basis.fixed_vertices);
  writer.write_matrix(basis.vectors);
}

BasisHeader read_basis_header(ContainerReader& reader, Eigen::Index max_size) {
  BasisHeader header;
  header.fingerprint = reader.read_u64("the mesh fingerprint");
  const std::uint64_t n = reader.read_u64("the vertex count");
  header.num_vertices_offset = reader.value_offset();
  if (n > static_cast<std::uint64_t>(max_basis_vertices)) {
    reader.fail_at(reader.value_offset(), "vertex count " + std::to_string(n) +
                                              " exceeds the limit of " +
                                              std::to_string(max_basis_vertices));
  }
  header.num_vertices = static_cast<Eigen::Index>(n);
  const std::uint64_t r = reader.read_u64("the basis size");
  header.size_offset = reader.value_offset();
  if (r > static_cast<std::uint64_t>(max_size)) {
    reader.fail_at(reader.value_offset(), "basis size " + std::to_string(r) +
                                              " exceeds the limit of " + std::to_string(max_size));
  }
  header.size = static_cast<Eigen::Index>(r);
  header.recipe = reader.read_string("the recipe");
  return header;
}

void check_basis_mesh(const ContainerReader& reader, const BasisHeader& header,
                      const VolumeMesh& mesh, std::string_view noun) {
  const std::uint64_t expected = mesh_fingerprint(mesh);
  if (header.fingerprint != expected) {
    std::string text = reader.source();
    text.append(": ").append(noun).append(" belongs to a different mesh: it was computed on a ");
    text.append("mesh with fingerprint ").append(fingerprint_text(header.fingerprint));
    text.append(" and ").append(std::to_string(header.num_vertices));
    text.append(" vertices, this mesh has fingerprint ").append(fingerprint_text(expected));
    text.append(" and ").append(std::to_string(mesh.num_vertices())).append(" vertices");
    throw Error(text);
  }
  if (header.num_vertices != mesh.num_vertices()) {  // only a forged file gets here
    reader.fail_at(header.num_vertices_offset,
                   "vertex count " + std::to_string(header.num_vertices) +
                       " differs from the mesh's " + std::to_string(mesh.num_vertices()) +
                       " although the fingerprints match");
  }
}

Basis read_basis_body(ContainerReader& reader, BasisHeader header) {
  Basis basis;
  basis.recipe = std::move(header.recipe);
  basis.fixed_vertices = reader.read_ints("the fixed vertices");
  if (const auto problem = fixed_vertex_problem(basis.fixed_vertices, header.num_vertices)) {
    reader.fail_at(reader.value_offset() + problem->first * sizeof(int), problem->second);
  }
  const std::size_t matrix_offset = reader.offset();
  basis.vectors = reader.read_matrix("the basis matrix U");
  check_shape(reader, matrix_offset, basis.vectors, "U", 3 * header.num_vertices, header.size,
              "3n × r from the header");
  check_finite(reader, basis.vectors, "U");
  return basis;
}

BasisFileInfo basis_file_info(const ContainerReader& reader, BasisHeader header,
                              Eigen::Index num_fixed_vertices) {
  BasisFileInfo info;
  info.format_version = reader.version();
  info.fingerprint = header.fingerprint;
  info.num_vertices = header.num_vertices;
  info.size = header.size;
  info.num_fixed_vertices = num_fixed_vertices;
  info.recipe = std::move(header.recipe);
  info.file_bytes = reader.file_bytes();
  return info;
}

void check_finite(const ContainerReader& reader, std::span<const double> values,
                  std::string_view name) {
  if (const auto k = first_non_finite(values)) {
    std::string text(name);
    text.append("[").append(std::to_string(*k)).append("] = ").append(number_text(values[*k]));
    reader.fail_at(reader.value_offset() + *k * sizeof(double), text.append(" is not finite"));
  }
}

void check_finite(const ContainerReader& reader, const Eigen::MatrixXd& matrix,
                  std::string_view name) {
  if (const auto k = first_non_finite(entries(matrix))) {
    reader.fail_at(reader.value_offset() + *k * sizeof(double), entry_text(name, matrix, *k));
  }
}

void check_shape(const ContainerReader& reader, std::size_t offset, const Eigen::MatrixXd& matrix,
                 std::string_view name, Eigen::Index rows, Eigen::Index cols,
                 std::string_view rule) {
  if (matrix.rows() != rows || matrix.cols() != cols) {
    std::string text(name);
    text.append(" is ").append(shape_text(matrix.rows(), matrix.cols())).append(", expected ");
    text.append(shape_text(rows, cols)).append(" (").append(rule).append(")");
    reader.fail_at(offset, text);
  }
}

}  // namespace detail

void write_basis(const std::filesystem::path& file, const Basis& basis, const VolumeMesh& mesh) {
  detail::check_basis_writable(file, "basis", basis, mesh, detail::max_basis_size);
  ContainerWriter writer(basis_file_format);
  detail::write_basis_payload(writer, basis, mesh);
  writer.write_file(file);
}

Basis read_basis(const std::filesystem::path& file, const VolumeMesh& mesh) {
  ContainerReader reader = ContainerReader::open(file, basis_file_format);
  detail::BasisHeader header = detail::read_basis_header(reader, detail::max_basis_size);
  detail::check_basis_mesh(reader, header, mesh, "the basis");
  Basis basis = detail::read_basis_body(reader, std::move(header));
  reader.finish("the basis matrix U");
  return basis;
}

BasisFileInfo read_basis_info(const std::filesystem::path& file) {
  ContainerReader reader = ContainerReader::open(file, basis_file_format);
  detail::BasisHeader header = detail::read_basis_header(reader, detail::max_basis_size);
  const auto num_fixed = static_cast<Eigen::Index>(reader.read_ints("the fixed vertices").size());
  return detail::basis_file_info(reader, std::move(header), num_fixed);
}

}  // namespace khz::reduced
