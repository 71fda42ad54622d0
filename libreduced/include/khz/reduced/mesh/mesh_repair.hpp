#pragma once
// Repair operations that turn messy input (soups, STL files, scans) into a clean surface.

#include <khz/reduced/export.hpp>
#include <khz/reduced/mesh/triangle_mesh.hpp>

#include <Eigen/Core>

namespace khz::reduced {

/// Merges vertices closer than `tolerance` (absolute, in mesh units; 0 merges only exact
/// duplicates), remaps triangles, and drops vertices no triangle uses. Colours of merged
/// vertices come from the lowest-indexed one. Returns the number of vertices removed.
/// @throws MeshError if the mesh is invalid or tolerance is negative or not finite.
KHZ_REDUCED_API Eigen::Index weld_vertices(TriangleMesh& mesh, double tolerance = 0.0);

/// Removes triangles with a repeated vertex or zero area (as MeshReport defines it) and
/// exact duplicates of earlier triangles (same vertex set). Returns the number removed.
/// @throws MeshError if the mesh is invalid.
KHZ_REDUCED_API Eigen::Index remove_degenerate_triangles(TriangleMesh& mesh);

/// Makes orientation consistent per connected component (CGAL Polygon Mesh Processing;
/// vertices of non-manifold configurations are duplicated so each component becomes
/// orientable), then, for a closed result, orients it to bound a volume (outward normals).
/// Returns true if the result is consistently oriented.
/// @throws MeshError if the mesh is invalid.
KHZ_REDUCED_API bool orient_consistently(TriangleMesh& mesh);

/// What repair_mesh() should do; each step runs in the order listed.
struct RepairOptions {
  double weld_tolerance = 0.0;        ///< Passed to weld_vertices(); negative skips welding.
  bool remove_degenerate = true;      ///< Run remove_degenerate_triangles().
  bool orient = true;                 ///< Run orient_consistently().
};

/// What repair_mesh() changed.
struct RepairSummary {
  Eigen::Index vertices_welded = 0;
  Eigen::Index triangles_removed = 0;
  bool oriented = false;  ///< Result consistently oriented (only set when options.orient).
};

/// Runs the selected repair steps in order: weld, remove degenerate, orient.
/// @throws MeshError if the mesh is invalid.
KHZ_REDUCED_API RepairSummary repair_mesh(TriangleMesh& mesh, const RepairOptions& options = {});

}  // namespace khz::reduced
