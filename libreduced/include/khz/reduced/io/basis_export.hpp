#pragma once
// Exports of a reduced basis to formats NumPy and MATLAB read, for analysis outside Kilohertz.
// These are one-way: Kilohertz reads bases back only from its own basis files (basis_file.hpp),
// which also tie the basis to its mesh.

#include <khz/reduced/basis/basis.hpp>
#include <khz/reduced/export.hpp>

#include <filesystem>
#include <string>

namespace khz::reduced {

/// U as a NumPy array file, format version 1.0: dtype '<f8' (little-endian float64), shape
/// (3n, r), fortran_order True, so the column-major data follows the header unchanged.
/// `numpy.load(file)` gives the 3n×r array; row 3v + c is coordinate c (x, y, z) of vertex v.
/// The header is padded so the data starts at a multiple of 64 bytes, as NumPy writes it. Only U is
/// stored; fixed vertices and recipe need write_basis_mat() or a basis file.
KHZ_REDUCED_API std::string format_basis_npy(const Basis& basis);

/// Writes format_basis_npy(basis) to `file` (by convention "*.npy"), atomically.
/// @throws IoError naming `file` and the system's reason.
KHZ_REDUCED_API void write_basis_npy(const std::filesystem::path& file, const Basis& basis);

/// The basis as a MATLAB Level 5 MAT-file (the uncompressed "-v6" format, which MATLAB's `load`,
/// GNU Octave and scipy.io.loadmat all read), little-endian, with three variables:
///   U               double, 3n × r; row 3v + c is coordinate c (x, y, z) of vertex v
///   fixed_vertices  int32, k × 1, ZERO-based vertex indices as in Kilohertz; in MATLAB the
///                   rows of U of vertex v are 3*v+1 : 3*v+3 (MATLAB indexes from 1)
///   recipe          char, 1 × length (stored as UTF-8; 0 × 0 when empty). Each byte that is
///                   not valid UTF-8 or encodes a character outside the Basic Multilingual
///                   Plane (where MATLAB's and scipy's lengths would differ) becomes '?'.
/// Level 5 rather than Level 4 because Level 4 has no integer or UTF-8 char classes and is
/// deprecated; not v7 because zlib gains little on dense doubles, nor v7.3 because it is HDF5.
/// Entries are written as they are (no finiteness check).
/// @throws Error if U exceeds what a Level 5 variable can hold (2^31 − 1 rows or columns, or
///         about 4 GiB of data: use write_basis_npy() then).
KHZ_REDUCED_API std::string format_basis_mat(const Basis& basis);

/// Writes format_basis_mat(basis) to `file` (by convention "*.mat"), atomically.
/// @throws Error as format_basis_mat(); IoError naming `file` and the system's reason.
KHZ_REDUCED_API void write_basis_mat(const std::filesystem::path& file, const Basis& basis);

}  // namespace khz::reduced
