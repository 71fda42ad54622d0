#pragma once
// Voxelization of a polygon soup into a hexahedral simulation mesh (thesis §2.5.2).

#include <khz/reduced/export.hpp>
#include <khz/reduced/mesh/triangle_mesh.hpp>
#include <khz/reduced/mesh/volume_mesh.hpp>

namespace khz::reduced {

/// Parameters of voxelize().
struct VoxelizeOptions {
  /// Voxels along each side of the grid cube, in [1, 1024]. Memory and time grow with the
  /// number of voxels kept (∝ resolution² for a surface shell, ∝ resolution³ when filled);
  /// fill_interior also needs resolution³ bits twice.
  int resolution = 64;
  /// Grid side over the largest extent of the surface's bounding box, ≥ 1. The thesis uses
  /// 1.2: a margin keeps the surface away from the grid's outer faces.
  double enlargement = 1.2;
  /// Also keep the voxels enclosed by the surface voxels (a solid instead of a shell).
  bool fill_interior = false;
};

/// Voxelizes a triangle mesh into equal cubes (thesis §2.5.2), for meshes that cannot be
/// tetrahedralized: polygon soups, open, non-manifold or self-intersecting surfaces.
///
/// The grid is a cube centred on the bounding box of the triangles' vertices, with side
/// enlargement × the box's largest extent, divided into resolution³ voxels. A voxel is kept if
/// its closed box touches at least one triangle (exact separating-axis test, so degenerate
/// triangles count as the segment or point they are). With fill_interior, the voxels no path of
/// face-adjacent untouched voxels connects to the grid's boundary are kept as well; for an open
/// surface that may be none.
///
/// Returns a hexahedral mesh, one element per kept voxel in grid order (x fastest, then y, then
/// z), every element an axis-aligned cube with VTK node order (positively oriented). Voxels share
/// their corner vertices; only used lattice points become vertices, numbered compactly in grid
/// order. element_groups is empty. Lengths are in the surface's units.
/// @throws Error if resolution is outside [1, 1024], enlargement is not finite or below 1, the
///         mesh has no triangles, or the triangles' vertices all coincide (zero extent).
/// @throws MeshError if the surface fails validate().
KHZ_REDUCED_API VolumeMesh voxelize(const TriangleMesh& soup, const VoxelizeOptions& options = {});

}  // namespace khz::reduced
