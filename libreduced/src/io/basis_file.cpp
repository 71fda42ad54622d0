#include <khz/reduced/errors.hpp>
#include <khz/reduced/io/basis_file.hpp>
#include <khz/reduced/io/mesh_fingerprint.hpp>

#include "detail/number_text.hpp"

#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace khz::reduced {
namespace {

/// Largest n: U's 3n rows must stay within the container's matrix dimension limit.
constexpr std::uint64_t max_vertices = std::numeric_limits<std::int32_t>::max() / 3;
constexpr std::uint64_t max_size = std::numeric_limits<std::int32_t>::max();

/// The header values every reader takes, with the offsets of the ones checked later.
struct Header {
  std::uint64_t fingerprint = 0;
  Eigen::Index num_vertices = 0;
  std::size_t num_vertices_offset = 0;
  Eigen::Index size = 0;
  std::string recipe;
};

Header read_header(ContainerReader& reader) {
  Header header;
  header.fingerprint = reader.read_u64("the mesh fingerprint");
  const std::uint64_t n = reader.read_u64("the vertex count");
  header.num_vertices_offset = reader.value_offset();
  if (n > max_vertices) {
    reader.fail_at(reader.value_offset(), "vertex count " + std::to_string(n) +
                                              " exceeds the limit of " +
                                              std::to_string(max_vertices));
  }
  header.num_vertices = static_cast<Eigen::Index>(n);
  const std::uint64_t r = reader.read_u64("the basis size");
  if (r > max_size) {
    reader.fail_at(reader.value_offset(), "basis size " + std::to_string(r) +
                                              " exceeds the limit of " + std::to_string(max_size));
  }
  header.size = static_cast<Eigen::Index>(r);
  header.recipe = reader.read_string("the recipe");
  return header;
}

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

/// The first non-finite entry of U in column-major order, as its index into U's data.
std::optional<Eigen::Index> first_non_finite(const Eigen::MatrixXd& u) {
  for (Eigen::Index k = 0; k < u.size(); ++k) {
    if (!std::isfinite(u.data()[k])) return k;
  }
  return std::nullopt;
}

std::string entry_text(const Eigen::MatrixXd& u, Eigen::Index k) {
  return "U(" + std::to_string(k % u.rows()) + ", " + std::to_string(k / u.rows()) +
         ") = " + detail::number_text(u.data()[k]) + " is not finite";
}

void check_writable(const std::filesystem::path& file, const Basis& basis, const VolumeMesh& mesh) {
  const auto fail = [&](const std::string& message) {
    throw Error(file.string() + ": cannot write basis: " + message);
  };
  const Eigen::Index n = mesh.num_vertices();
  if (static_cast<std::uint64_t>(n) > max_vertices) {
    fail("the mesh has " + std::to_string(n) + " vertices, more than the " +
         std::to_string(max_vertices) + " a basis file can hold");
  }
  if (static_cast<std::uint64_t>(basis.size()) > max_size) {
    fail("r = " + std::to_string(basis.size()) + " exceeds the limit of " +
         std::to_string(max_size));
  }
  if (basis.vectors.rows() != 3 * n) {
    fail("U has " + std::to_string(basis.vectors.rows()) + " rows, expected 3·" +
         std::to_string(n) + " = " + std::to_string(3 * n) + " (3 per mesh vertex)");
  }
  if (const auto k = first_non_finite(basis.vectors)) fail(entry_text(basis.vectors, *k));
  if (const auto problem = fixed_vertex_problem(basis.fixed_vertices, n)) fail(problem->second);
}

}  // namespace

void write_basis(const std::filesystem::path& file, const Basis& basis, const VolumeMesh& mesh) {
  check_writable(file, basis, mesh);
  ContainerWriter writer(basis_file_format);
  writer.write_u64(mesh_fingerprint(mesh));
  writer.write_u64(static_cast<std::uint64_t>(mesh.num_vertices()));
  writer.write_u64(static_cast<std::uint64_t>(basis.size()));
  writer.write_string(basis.recipe);
  writer.write_ints(basis.fixed_vertices);
  writer.write_matrix(basis.vectors);
  writer.write_file(file);
}

Basis read_basis(const std::filesystem::path& file, const VolumeMesh& mesh) {
  ContainerReader reader = ContainerReader::open(file, basis_file_format);
  Header header = read_header(reader);
  const std::uint64_t expected = mesh_fingerprint(mesh);
  if (header.fingerprint != expected) {
    throw Error(file.string() + ": the basis belongs to a different mesh: it was computed on a " +
                "mesh with fingerprint " + fingerprint_text(header.fingerprint) + " and " +
                std::to_string(header.num_vertices) + " vertices, this mesh has fingerprint " +
                fingerprint_text(expected) + " and " + std::to_string(mesh.num_vertices()) +
                " vertices");
  }
  if (header.num_vertices != mesh.num_vertices()) {  // only a forged file gets here
    reader.fail_at(header.num_vertices_offset,
                   "vertex count " + std::to_string(header.num_vertices) +
                       " differs from the mesh's " + std::to_string(mesh.num_vertices()) +
                       " although the fingerprints match");
  }

  Basis basis;
  basis.recipe = std::move(header.recipe);
  basis.fixed_vertices = reader.read_ints("the fixed vertices");
  if (const auto problem = fixed_vertex_problem(basis.fixed_vertices, header.num_vertices)) {
    reader.fail_at(reader.value_offset() + problem->first * sizeof(int), problem->second);
  }

  const std::size_t matrix_offset = reader.offset();
  basis.vectors = reader.read_matrix("the basis matrix U");
  const Eigen::Index rows = 3 * header.num_vertices;
  if (basis.vectors.rows() != rows || basis.vectors.cols() != header.size) {
    reader.fail_at(matrix_offset, "U is " + std::to_string(basis.vectors.rows()) + "×" +
                                      std::to_string(basis.vectors.cols()) + ", the header says " +
                                      std::to_string(rows) + "×" + std::to_string(header.size));
  }
  if (const auto k = first_non_finite(basis.vectors)) {
    reader.fail_at(reader.value_offset() + static_cast<std::size_t>(*k) * sizeof(double),
                   entry_text(basis.vectors, *k));
  }
  reader.finish("the basis matrix U");
  return basis;
}

BasisFileInfo read_basis_info(const std::filesystem::path& file) {
  ContainerReader reader = ContainerReader::open(file, basis_file_format);
  Header header = read_header(reader);
  BasisFileInfo info;
  info.format_version = reader.version();
  info.fingerprint = header.fingerprint;
  info.num_vertices = header.num_vertices;
  info.size = header.size;
  info.recipe = std::move(header.recipe);
  info.num_fixed_vertices =
      static_cast<Eigen::Index>(reader.read_ints("the fixed vertices").size());
  info.file_bytes = reader.file_bytes();
  return info;
}

}  // namespace khz::reduced
