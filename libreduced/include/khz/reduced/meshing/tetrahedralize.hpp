#pragma once
// Tetrahedral meshing of the volume enclosed by a closed surface (CGAL Mesh_3 inside).

#include <khz/reduced/export.hpp>
#include <khz/reduced/mesh/triangle_mesh.hpp>
#include <khz/reduced/mesh/volume_mesh.hpp>

#include <cstdint>

namespace khz::reduced {

/// Mesh criteria of tetrahedralize(). Lengths are in the surface's units; 0 means automatic,
/// a fraction of the diagonal d of the surface's bounding box. The defaults give about 21 000
/// tetrahedra (6 600 vertices) for CGAL's dino.off in about 0.5 s (Release), with a volume 0.8 %
/// below the enclosed one; the automatic sizes scale with a shape's size, not its detail: raise
/// them for coarser, lower for finer meshes.
struct TetrahedralizeOptions {
  /// Upper bound of the radius of the surface Delaunay balls, ~ the boundary triangles' size.
  /// Automatic: d / 45.
  double facet_size = 0.0;
  /// Upper bound of the distance between a boundary triangle's circumcentre and the input
  /// surface, i.e. how closely the boundary follows curved parts; the main driver of the
  /// element count. Automatic: d / 1000.
  double facet_distance = 0.0;
  /// Lower bound of the boundary triangles' angles, degrees, in [0, 30] (termination is
  /// guaranteed only up to 30; 0 disables the bound).
  double facet_angle = 25.0;
  /// Upper bound of the tetrahedra's circumradius. Automatic: the facet size.
  double cell_size = 0.0;
  /// Upper bound of circumradius / shortest edge of the tetrahedra, ≥ 2 (the smallest bound for
  /// which Delaunay refinement is guaranteed to terminate). Slivers pass it; see below.
  double cell_radius_edge_ratio = 2.0;
  /// Seed of the random choices (initial surface points): equal seeds and inputs give identical
  /// meshes with the same build, whatever the machine's load (different compiler flags, e.g.
  /// -march=native with FMA, may round differently and give a different mesh).
  std::uint32_t seed = 0;
  /// Sliver removal works on the tetrahedra whose smallest dihedral angle is below this bound,
  /// degrees (0: on all of them, much slower). Exudation improves most slivers, not all: dino.off
  /// keeps a smallest dihedral angle of 3.8° (0.14° without it), 10° with perturb.
  double sliver_bound = 10.0;
  /// Run sliver perturbation after refinement: moves vertices, better angles, slow (dino.off:
  /// 4.2 s instead of 0.5 s at the default bound).
  bool perturb = false;
  /// Run sliver exudation after refinement: changes the connectivity, not the vertices (dino.off:
  /// +0.1 s).
  bool exude = true;
};

/// Tetrahedralizes the volume enclosed by `closed_surface` with CGAL's Mesh_3 Delaunay
/// refinement (single-threaded, so deterministic for a given seed). Boundary vertices lie on
/// the input surface but are not its vertices: the boundary approximates the surface within
/// facet_distance, and sharp edges are not preserved.
///
/// Returns positively oriented tetrahedra, vertices numbered compactly (only those of the
/// tetrahedra); element_groups is empty. Self-intersections of the surface are not detected and
/// give an undefined (but valid) mesh.
/// @throws MeshError if the surface fails validate(), has no triangles, or is not closed, edge-
///         and vertex-manifold, consistently oriented and free of degenerate triangles (see
///         analyze_mesh()); the message lists the problems and suggests repair_mesh() or, for
///         polygon soups, voxelize().
/// @throws Error if an option is out of range (negative or non-finite size, facet_angle outside
///         [0, 30], cell_radius_edge_ratio < 2, negative sliver_bound) or the criteria are so
///         coarse that no tetrahedron is produced.
KHZ_REDUCED_API VolumeMesh tetrahedralize(const TriangleMesh& closed_surface,
                                          const TetrahedralizeOptions& options = {});

}  // namespace khz::reduced
