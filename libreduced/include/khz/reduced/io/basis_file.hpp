#pragma once
// Basis files (".khzbasis"): a reduced basis stored with the fingerprint of the mesh it belongs
// to, in the checked binary container of binary_container.hpp.
//
// Format version 1. Container magic "KHZBASIS"; the payload, in order:
//
//   u64     mesh fingerprint (mesh_fingerprint() of the mesh U was computed on)
//   u64     n, the mesh's vertex count
//   u64     r, the number of basis vectors
//   string  recipe (Basis::recipe, UTF-8)
//   ints    fixed vertices: zero-based, sorted, distinct, each in [0, n)
//   matrix  U, 3n × r, column-major; row 3v + c is coordinate c (x, y, z) of vertex v
//
// Everything is little-endian and the whole file is covered by an XXH3-64 checksum, so the
// values read back are bit for bit the values written.

#include <khz/reduced/basis/basis.hpp>
#include <khz/reduced/export.hpp>
#include <khz/reduced/io/binary_container.hpp>
#include <khz/reduced/mesh/volume_mesh.hpp>

#include <Eigen/Core>

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

namespace khz::reduced {

/// The extension basis files use (the readers do not insist on it).
inline constexpr std::string_view basis_file_extension = ".khzbasis";

/// The container format of basis files; version is the newest this build writes and reads.
inline constexpr ContainerFormat basis_file_format{"KHZBASIS", "Kilohertz basis file", 1};

/// What a basis file's header says, read without the mesh (for `khz info`).
struct BasisFileInfo {
  std::uint32_t format_version = 0;  ///< The file's format version (1 ≤ v ≤ basis_file_format).
  std::uint64_t fingerprint = 0;     ///< mesh_fingerprint() of the mesh the basis belongs to.
  Eigen::Index num_vertices = 0;     ///< n, the mesh's vertex count (U has 3n rows).
  Eigen::Index size = 0;             ///< r, the number of basis vectors.
  Eigen::Index num_fixed_vertices = 0;  ///< Length of Basis::fixed_vertices.
  std::string recipe;                   ///< Basis::recipe.
  std::uintmax_t file_bytes = 0;        ///< Size of the file on disk.
};

/// Writes `basis` for `mesh` to `file` (by convention with basis_file_extension), atomically:
/// a crash or a failure leaves the previous file, if any, untouched.
/// @param basis  U must be 3·mesh.num_vertices() × r with finite entries; fixed_vertices sorted,
///               distinct and in [0, #V). r = 0 is allowed.
/// @param mesh   The mesh the basis was computed on; only its fingerprint and vertex count are
///               stored.
/// @throws Error naming `file` and the offending entry if the basis violates the above (nothing
///         is written); IoError naming `file` and the system's reason if writing fails.
KHZ_REDUCED_API void write_basis(const std::filesystem::path& file, const Basis& basis,
                                 const VolumeMesh& mesh);

/// Reads a basis file written for `mesh`. The result is bit for bit what write_basis() got.
/// @throws IoError if the file cannot be read.
/// @throws ParseError "<file>: byte <offset>: <message>" if it is not a basis file, was written
///         by a newer format version, is truncated or corrupted (checksum), or holds inconsistent
///         values (sizes, fixed vertex out of range or unsorted, non-finite entry in U).
/// @throws Error if the basis belongs to a different mesh (the fingerprints differ); the message
///         shows both fingerprints and vertex counts.
KHZ_REDUCED_API Basis read_basis(const std::filesystem::path& file, const VolumeMesh& mesh);

/// Reads a basis file's header (format version, fingerprint, n, r, fixed-vertex count, recipe)
/// without a mesh. The whole file is read and its checksum verified, so a file this accepts is
/// intact; U itself is neither checked nor kept.
/// @throws IoError, ParseError as read_basis().
KHZ_REDUCED_API BasisFileInfo read_basis_info(const std::filesystem::path& file);

}  // namespace khz::reduced
