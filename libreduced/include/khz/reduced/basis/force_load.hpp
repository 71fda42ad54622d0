#pragma once
// Recorded force loads: the input of the sketch basis (thesis §2.8.2). While a user pushes a
// fast linear model around, the forces they apply are recorded to disk; each recorded load is a
// handful of point forces on mesh vertices.

#include <khz/reduced/export.hpp>

#include <Eigen/Core>

#include <filesystem>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace khz::reduced {

/// One concentrated force on a mesh vertex.
struct PointForce {
  int vertex = 0;                                   ///< Vertex index, 0-based.
  Eigen::Vector3d force = Eigen::Vector3d::Zero();  ///< Force on the vertex (N).
};

/// A static force load: a sparse set of point forces. A vertex may appear more than once; its
/// forces then add up. An empty load is the zero load.
struct KHZ_REDUCED_API ForceLoad {
  std::vector<PointForce> forces;

  /// Checks every vertex index against [0, num_vertices) and every force for finiteness.
  /// @throws Error naming the offending point force (position in `forces`) and vertex.
  void validate(Eigen::Index num_vertices) const;

  /// The full force vector f (N) of a mesh with `num_vertices` vertices: 3·num_vertices
  /// entries, entry 3v+i the sum of the i-th components of the forces on vertex v, zero
  /// elsewhere. What solve_static() and FullNewmark::step() take.
  /// @throws Error as validate().
  Eigen::VectorXd to_vector(Eigen::Index num_vertices) const;
};

/// Pairwise distances ‖f_a − f_b‖ (N) between the full force vectors of the loads: N × N,
/// symmetric, zero diagonal. Computed exactly on the sparse forces (no cancellation), so
/// loads that differ by less than round-off are at distance 0 only if they are identical.
/// Vertex indices are not range-checked here (call validate() for that).
/// @throws Error if a force is not finite or a vertex index is negative.
KHZ_REDUCED_API Eigen::MatrixXd force_distances(std::span<const ForceLoad> loads);

/// Parses a recorded list of loads from CSV text:
///
///     load,vertex,fx,fy,fz
///     0,120,0,0,-15.5
///     0,121,0,0,-15.5
///     1,120,3.25,0,-20
///
/// The first content line is the header, exactly these five names. Every other content line is
/// one point force: load id, vertex index (0-based), force components (N). The rows of a load
/// are consecutive and load ids count up from 0 in steps of one, so the id of a load is its
/// position in the returned list. Fields may be padded with spaces or tabs; blank lines and
/// lines whose first non-blank character is '#' are ignored; numbers are read with the C locale
/// ('.' as decimal point). A file with only the header holds no loads.
///
/// @param data         the file's bytes.
/// @param source       name used in error messages (usually the path).
/// @param num_vertices vertices of the mesh the loads act on: every vertex index must lie in
///                     [0, num_vertices).
/// @throws ParseError "<source>:<line>: <message>" for a missing or wrong header, a row without
///         exactly five fields, a field that is not an integer / finite number, a vertex out of
///         range, or a load id out of sequence.
KHZ_REDUCED_API std::vector<ForceLoad> parse_force_loads(std::string_view data,
                                                         const std::string& source,
                                                         Eigen::Index num_vertices);

/// The CSV text parse_force_loads() reads, with numbers printed to round-trip exactly.
/// @throws Error if a load has no point forces (the format cannot represent an empty load),
///         naming it, or a force is not finite.
KHZ_REDUCED_API std::string format_force_loads(std::span<const ForceLoad> loads);

/// Reads a load file (see parse_force_loads()).
/// @throws IoError if the file cannot be read; ParseError as parse_force_loads().
KHZ_REDUCED_API std::vector<ForceLoad> read_force_loads(const std::filesystem::path& file,
                                                        Eigen::Index num_vertices);

/// Writes a load file (see format_force_loads()).
/// @throws Error as format_force_loads(); IoError if the file cannot be written.
KHZ_REDUCED_API void write_force_loads(const std::filesystem::path& file,
                                       std::span<const ForceLoad> loads);

}  // namespace khz::reduced
