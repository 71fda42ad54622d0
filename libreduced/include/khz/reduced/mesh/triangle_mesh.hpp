#pragma once
// Indexed triangle mesh: the surface representation every Kilohertz precompute starts from.

#include <khz/reduced/export.hpp>

#include <Eigen/Core>

namespace khz::reduced {

/// #V×3 vertex positions, one row per vertex, in the file's length unit (metres in simulation).
using VertexMatrix = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;
/// #F×3 zero-based vertex indices, one row per triangle.
using TriangleMatrix = Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor>;
/// #V×4 RGBA vertex colours, each channel in [0, 1].
using ColorMatrix = Eigen::Matrix<float, Eigen::Dynamic, 4, Eigen::RowMajor>;

/// A triangle mesh as stored in a file: positions, triangles and optional vertex colours.
///
/// Nothing is assumed about topology: a TriangleMesh may be a closed manifold, an open surface
/// or a polygon soup (use analyze_mesh() to find out). Orientation convention: triangles are
/// counter-clockwise seen from outside, so normals (b−a)×(c−a) point outwards.
struct TriangleMesh {
  VertexMatrix vertices;      ///< #V×3 positions.
  TriangleMatrix triangles;   ///< #F×3 indices into `vertices`.
  ColorMatrix vertex_colors;  ///< Empty, or #V×4 RGBA in [0, 1] (e.g. from a COFF or PLY file).

  Eigen::Index num_vertices() const noexcept { return vertices.rows(); }
  Eigen::Index num_triangles() const noexcept { return triangles.rows(); }
  bool has_vertex_colors() const noexcept { return vertex_colors.rows() > 0; }
};

/// Checks the invariants every algorithm relies on: finite coordinates, indices in
/// [0, #V), vertex_colors empty or #V rows with channels in [0, 1].
/// @throws MeshError naming the first offending vertex or triangle.
KHZ_REDUCED_API void validate(const TriangleMesh& mesh);

}  // namespace khz::reduced
