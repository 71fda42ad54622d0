#pragma once
// Topological and geometric diagnosis of a triangle mesh.

#include <khz/reduced/export.hpp>
#include <khz/reduced/mesh/triangle_mesh.hpp>

#include <Eigen/Geometry>

#include <iosfwd>
#include <vector>

namespace khz::reduced {

/// What analyze_mesh() found; index lists are sorted.
///
/// Topology (edges, manifoldness, orientation, components, Euler characteristic) is purely
/// combinatorial: every triangle with three distinct vertex indices takes part, zero-area and
/// duplicate ones included (so a duplicated triangle makes its edges non-manifold, and a
/// closed surface with a sliver stays closed). Triangles repeating an index take no part.
struct MeshReport {
  Eigen::Index num_vertices = 0;
  Eigen::Index num_triangles = 0;
  Eigen::AlignedBox3d bounding_box;  ///< Of the referenced vertices; empty for an empty mesh.

  Eigen::Index num_edges = 0;           ///< Undirected vertex pairs of the triangles taking part.
  Eigen::Index num_boundary_edges = 0;  ///< Edges with exactly one incident triangle.
  Eigen::Index num_non_manifold_edges = 0;  ///< Edges with three or more incident triangles.
  /// Vertices whose incident triangles form more than one fan (a "bow tie"; a fan is a set
  /// of triangles connected through edges at the vertex). Vertices of non-manifold edges are
  /// not counted here.
  Eigen::Index num_non_manifold_vertices = 0;
  Eigen::Index num_unreferenced_vertices = 0;  ///< Vertices no triangle uses.
  /// Vertices whose position equals that of a lower-indexed vertex exactly (weld candidates).
  Eigen::Index num_duplicate_vertices = 0;

  /// Triangles with a repeated index or zero area (|(b−a)×(c−a)| ≤ 1e-12·diagonal², the
  /// diagonal of bounding_box).
  std::vector<Eigen::Index> degenerate_triangles;
  /// Triangles with three distinct vertices using the same vertices as a lower-indexed
  /// triangle (in any order).
  std::vector<Eigen::Index> duplicate_triangles;

  Eigen::Index num_components = 0;  ///< Connected components of triangles sharing an edge.

  bool edge_manifold = false;    ///< No non-manifold edge.
  bool vertex_manifold = false;  ///< edge_manifold and no non-manifold vertex.
  /// edge_manifold, and every edge with two triangles is traversed in opposite directions by
  /// them (a consistent orientation). Non-manifold vertices do not matter.
  bool consistently_oriented = false;
  /// Watertight: at least one edge, vertex_manifold and no boundary edge.
  bool closed = false;

  double surface_area = 0.0;  ///< Sum of the areas of all triangles.
  /// Signed enclosed volume Σ (a−o)·((b−o)×(c−o))/6 over all triangles, o the centre of
  /// bounding_box (for a closed surface the same as Σ a·(b×c)/6, with less cancellation);
  /// meaningful when closed and consistently oriented (positive for outward-facing triangles).
  double signed_volume = 0.0;
  /// V − E + F of the triangles taking part in the topology and the vertices they use.
  Eigen::Index euler_characteristic = 0;
};

/// Analyzes `mesh` (which must pass validate()). O(F log F), no CGAL involved, so it can
/// diagnose meshes CGAL would refuse.
/// @throws MeshError if the mesh is invalid.
KHZ_REDUCED_API MeshReport analyze_mesh(const TriangleMesh& mesh);

/// Human-readable multi-line summary of a report (used by `khz info`).
KHZ_REDUCED_API std::ostream& operator<<(std::ostream& out, const MeshReport& report);

}  // namespace khz::reduced
