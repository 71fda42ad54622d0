#pragma once
// Topological and geometric diagnosis of a triangle mesh.

#include <khz/reduced/export.hpp>
#include <khz/reduced/mesh/triangle_mesh.hpp>

#include <Eigen/Geometry>

#include <iosfwd>
#include <vector>

namespace khz::reduced {

/// What analyze_mesh() found. Edges are undirected vertex pairs used by at least one
/// non-degenerate triangle; index lists are sorted.
struct MeshReport {
  Eigen::Index num_vertices = 0;
  Eigen::Index num_triangles = 0;
  Eigen::AlignedBox3d bounding_box;  ///< Of the referenced vertices; empty for an empty mesh.

  Eigen::Index num_edges = 0;
  Eigen::Index num_boundary_edges = 0;      ///< Edges with exactly one incident triangle.
  Eigen::Index num_non_manifold_edges = 0;  ///< Edges with three or more incident triangles.
  /// Vertices whose incident triangles form more than one fan (a "bow tie"), among vertices
  /// on manifold edges only.
  Eigen::Index num_non_manifold_vertices = 0;
  Eigen::Index num_unreferenced_vertices = 0;  ///< Vertices no triangle uses.
  /// Vertices whose position equals that of a lower-indexed vertex exactly (weld candidates).
  Eigen::Index num_duplicate_vertices = 0;

  /// Triangles with a repeated index or zero area (|(b−a)×(c−a)| ≤ 1e-12·diagonal²).
  std::vector<Eigen::Index> degenerate_triangles;
  /// Triangles using the same three vertices as a lower-indexed triangle (any order).
  std::vector<Eigen::Index> duplicate_triangles;

  Eigen::Index num_components = 0;  ///< Connected components of triangles sharing an edge.

  bool edge_manifold = false;    ///< No non-manifold edge.
  bool vertex_manifold = false;  ///< edge_manifold and no non-manifold vertex.
  /// Every edge with two triangles is traversed in opposite directions by them (a
  /// consistent orientation); edges of non-manifold fans make this false.
  bool consistently_oriented = false;
  /// Watertight: non-empty, vertex_manifold and no boundary edge.
  bool closed = false;

  double surface_area = 0.0;  ///< Sum of triangle areas.
  /// Signed enclosed volume Σ a·(b×c)/6; meaningful when closed and consistently oriented
  /// (positive for outward-facing triangles).
  double signed_volume = 0.0;
  Eigen::Index euler_characteristic = 0;  ///< V − E + F over referenced vertices.
};

/// Analyzes `mesh` (which must pass validate()). O(F log F), no CGAL involved, so it can
/// diagnose meshes CGAL would refuse.
/// @throws MeshError if the mesh is invalid.
KHZ_REDUCED_API MeshReport analyze_mesh(const TriangleMesh& mesh);

/// Human-readable multi-line summary of a report (used by `khz info`).
KHZ_REDUCED_API std::ostream& operator<<(std::ostream& out, const MeshReport& report);

}  // namespace khz::reduced
