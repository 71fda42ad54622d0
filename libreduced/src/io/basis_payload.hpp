#pragma once
// The basis payload that basis files and reduced model files share (see basis_file.hpp for its
// layout: fingerprint, n, r, recipe, fixed vertices, U), and the value checks their readers
// share. Defined in basis_file.cpp.

#include <khz/reduced/basis/basis.hpp>
#include <khz/reduced/io/basis_file.hpp>
#include <khz/reduced/io/binary_container.hpp>
#include <khz/reduced/mesh/volume_mesh.hpp>

#include <Eigen/Core>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <span>
#include <string>
#include <string_view>

namespace khz::reduced::detail {

/// The header values of a basis payload, with the offsets of the ones checked later.
struct BasisHeader {
  std::uint64_t fingerprint = 0;
  Eigen::Index num_vertices = 0;
  std::size_t num_vertices_offset = 0;
  Eigen::Index size = 0;  // r
  std::size_t size_offset = 0;
  std::string recipe;
};

/// Largest n: U's 3n rows must stay within the container's matrix dimension limit.
inline constexpr Eigen::Index max_basis_vertices = std::numeric_limits<std::int32_t>::max() / 3;
/// Largest r of a basis file (the container's matrix dimension limit).
inline constexpr Eigen::Index max_basis_size = std::numeric_limits<std::int32_t>::max();

/// Throws Error "<file>: cannot write <noun>: <problem>" if `basis` cannot be stored for `mesh`:
/// too many vertices, more than `max_size` vectors, U not 3n rows, a non-finite entry, bad fixed
/// vertices.
void check_basis_writable(const std::filesystem::path& file, std::string_view noun,
                          const Basis& basis, const VolumeMesh& mesh, Eigen::Index max_size);
/// Appends the basis payload of `basis` for `mesh`.
void write_basis_payload(ContainerWriter& writer, const Basis& basis, const VolumeMesh& mesh);

/// Reads the header values (fingerprint, n, r, recipe) and checks n ≤ max_basis_vertices and
/// r ≤ max_size.
BasisHeader read_basis_header(ContainerReader& reader, Eigen::Index max_size);
/// Throws Error if the payload belongs to a different mesh ("<file>: <noun> belongs to a
/// different mesh: ..." with both fingerprints and vertex counts), ParseError if only the vertex
/// counts differ (a forged file).
void check_basis_mesh(const ContainerReader& reader, const BasisHeader& header,
                      const VolumeMesh& mesh, std::string_view noun);
/// Reads the rest of the payload (fixed vertices, U) after read_basis_header() and checks it
/// against the header: fixed vertices sorted, distinct and in [0, n), U 3n × r and finite.
Basis read_basis_body(ContainerReader& reader, BasisHeader header);

/// The facts BasisFileInfo reports, from a header and the fixed-vertex count.
BasisFileInfo basis_file_info(const ContainerReader& reader, BasisHeader header,
                              Eigen::Index num_fixed_vertices);

/// Throws ParseError at the first non-finite entry of `values`, which must be the value just read
/// (its data starting at reader.value_offset()): "<name>[k] = nan is not finite".
void check_finite(const ContainerReader& reader, std::span<const double> values,
                  std::string_view name);
/// The same for a matrix just read: "<name>(i, j) = inf is not finite".
void check_finite(const ContainerReader& reader, const Eigen::MatrixXd& matrix,
                  std::string_view name);
/// Throws ParseError at the matrix's row count unless the matrix just read, which started at
/// `offset`, is rows × cols: "<name> is a×b, expected rows×cols (<rule>)".
void check_shape(const ContainerReader& reader, std::size_t offset, const Eigen::MatrixXd& matrix,
                 std::string_view name, Eigen::Index rows, Eigen::Index cols,
                 std::string_view rule);

}  // namespace khz::reduced::detail
