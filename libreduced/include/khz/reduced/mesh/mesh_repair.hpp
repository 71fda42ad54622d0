#pragma once
// Repair operations that turn messy input (soups, STL files, scans) into a clean surface.

#include <khz/reduced/export.hpp>
#include <khz/reduced/mesh/triangle_mesh.hpp>

#include <Eigen/Core>

namespace khz::reduced {

/// Merges vertices within `tolerance` of each other (distance ≤ tolerance, absolute, in mesh
/// units; chains of close vertices merge transitively; 0 merges only exact duplicates), remaps
/// triangles, and drops vertices no triangle uses (before merging, so they never bridge two
/// used ones). Surviving vertices keep their relative order, and a merged vertex keeps the
/// position and colour of its lowest-indexed member.
/// Triangles that collapse are kept (see remove_degenerate_triangles()). Returns the number
/// of vertices removed.
/// @throws MeshError if the mesh is invalid or tolerance is negative or not finite.
KHZ_REDUCED_API Eigen::Index weld_vertices(TriangleMesh& mesh, double tolerance = 0.0);

/// Removes triangles with a repeated vertex or zero area (as MeshReport defines it) and
/// exact duplicates of earlier triangles (same vertex set), keeping the order of the rest.
/// Vertices are untouched. Note that removing a zero-area triangle with three distinct
/// vertices leaves boundary edges (a crack) in a surface that was closed. Returns the number
/// removed.
/// @throws MeshError if the mesh is invalid.
KHZ_REDUCED_API Eigen::Index remove_degenerate_triangles(TriangleMesh& mesh);

/// Makes orientation consistent per connected component (CGAL Polygon Mesh Processing;
/// vertices of non-manifold configurations are duplicated so each component becomes
/// orientable: copies are appended with the original's position and colour), then, if the
/// whole result is closed, orients it to bound a volume: outward normals, cavities facing
/// inwards. A closed result that self-intersects or has degenerate triangles, which CGAL's
/// volume orientation does not accept, gets each component turned outward instead. Triangles
/// repeating a vertex are left as they are. Returns true if the result is consistently
/// oriented.
/// @throws MeshError if the mesh is invalid.
KHZ_REDUCED_API bool orient_consistently(TriangleMesh& mesh);

/// What fill_holes() did.
struct HoleFilling {
  Eigen::Index filled = 0;  ///< Holes closed.
  /// Holes left open: no triangulation was found, or its triangles would have given an existing
  /// edge a third triangle (a loop bridged by an edge of the surface, as where holes nearly meet).
  Eigen::Index left_open = 0;
};

/// Closes every hole it can: each loop of boundary edges (edges only one triangle uses) is filled
/// with triangles over the loop's own vertices, no new vertices, by CGAL's
/// triangulate_hole_polyline() (Liepa 2003: the triangulation of least worst dihedral angle,
/// then least area), oriented like the surface around it. Meant for the small holes of scans
/// (ChineseDragon-10kv.off has one of 6 edges) so that the surface bounds a volume; a large
/// opening is capped too, flat or curved as the loop runs. The result stays edge-manifold: a hole
/// whose filling would break that is left open and counted. Vertex colours are kept (no vertex
/// is added).
/// @throws MeshError if the mesh is invalid, has non-manifold edges or is not consistently
///         oriented (orient_consistently() first), or if two holes share a vertex.
KHZ_REDUCED_API HoleFilling fill_holes(TriangleMesh& mesh);

/// What repair_mesh() should do; each step runs in the order listed.
struct RepairOptions {
  double weld_tolerance = 0.0;    ///< Passed to weld_vertices(); negative skips welding.
  bool remove_degenerate = true;  ///< Run remove_degenerate_triangles().
  bool orient = true;             ///< Run orient_consistently().
  bool fill_holes = false;        ///< Then run fill_holes() (needs an oriented surface).
};

/// What repair_mesh() changed.
struct RepairSummary {
  Eigen::Index vertices_welded = 0;    ///< Vertices weld_vertices() removed.
  Eigen::Index triangles_removed = 0;  ///< Triangles remove_degenerate_triangles() removed.
  /// Copies orient_consistently() appended at non-manifold vertices and edges so that each
  /// component can be oriented. Welding the boundaries of holes or cracks together often makes
  /// such vertices, and orienting then splits them again at the same positions: a mesh that
  /// must stay welded is repaired with options.orient = false.
  Eigen::Index vertices_split = 0;
  bool oriented = false;  ///< Result consistently oriented (only set when options.orient).
  HoleFilling holes;      ///< What fill_holes() did (options.fill_holes).
};

/// Runs the selected repair steps in order: weld, remove degenerate, orient, fill holes.
/// @throws MeshError if the mesh is invalid.
KHZ_REDUCED_API RepairSummary repair_mesh(TriangleMesh& mesh, const RepairOptions& options = {});

}  // namespace khz::reduced
