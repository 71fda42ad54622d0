#pragma once
// Signed and unsigned distance fields of triangle meshes on regular grids (thesis §3.11).

#include <khz/contact/common.hpp>
#include <khz/contact/export.hpp>
#include <khz/contact/field/distance_grid.hpp>
#include <khz/contact/field/grid_geometry.hpp>

#include <cstdint>
#include <optional>

namespace khz::contact {

/// Options of signed_distance_field() and unsigned_distance_field().
struct DistanceFieldOptions {
  /// Cells per axis of the cube around the mesh (GridGeometry::cube_around); ignored when
  /// `geometry` is given. 512 cells take 513³ floats, 540 MB.
  int cells = 128;
  /// Edge of the cube over the mesh's longest side (thesis §3.11: 1.5).
  double box_expansion = 1.5;
  /// A given grid instead of the cube around the mesh (e.g. to sample two fields alike). It
  /// need not contain the mesh; if it does not, its boundary nodes are computed exactly too
  /// (about 5 µs each), so that triangles outside the box still reach the nodes they are
  /// closest to.
  std::optional<GridGeometry> geometry;
  /// Nodes within this many cell spacings of the mesh get exact point-triangle distances (and,
  /// for signed fields, the side the closest feature's pseudonormal gives); the others are
  /// filled by closest-triangle propagation (see signed_distance_field()). At least √3 ≈ 1.732,
  /// so that a node beyond it can take its side from any neighbour; +infinity makes every node
  /// exact, which costs about 5 µs of CPU per node far from the mesh instead of under 1 µs.
  double exact_band = 3.0;
  /// Largest node storage allowed (bytes): 4 bytes per node. The computation works in place in
  /// the result's values, so this is also its memory per node; on top come the mesh's search
  /// structures (about 300 bytes per triangle) and, for signed fields, about 40 bytes per grid
  /// row and one plane per thread (together about 10/cells of the nodes' bytes: 4% at 256
  /// cells). A larger grid is refused before anything is allocated.
  std::int64_t memory_budget_bytes = std::int64_t{1} << 30;
  /// Reports stage "distance field" in units of 8 grid planes of a pass (band search, the
  /// box's faces when the mesh reaches outside it, the regions' sides for signed fields, final
  /// values) or 16 planes of one of the six sweeps: about 3·(cells + 1)/4 units, each a fraction
  /// of a second at 512 cells. Returning false cancels within one unit (Cancelled).
  ProgressCallback progress;
};

/// The signed distance field (negative inside) of a closed, consistently oriented manifold mesh.
/// In parallel (OpenMP) from 96² nodes per plane up (below, barriers would cost more than
/// they save); the result does not depend on the thread count. Cost: about 0.5 µs of
/// CPU per node (bunny00.off, 75k triangles: 4.5 s for 256³ cells on 2 cores; see
/// bench_distance_field).
///
/// How (thesis §3.11 leaves it open):
/// 1. Band: every node within `exact_band` spacings of the mesh gets its closest triangle from a
///    bounding-volume hierarchy, its exact distance, and its side from the angle-weighted
///    pseudonormal of the closest feature (MeshDistance; exact for closed manifolds without
///    self-intersections, Bærentzen & Aanæs 2005).
/// 2. Fill: the closest triangles spread to all other nodes by six cone sweeps (±x, ±y, ±z):
///    plane by plane, each node keeps the closest of its own candidate and those of the 3×3
///    nodes behind it. A node's value is the exact distance to the triangle it ends with, so
///    it is never below the true distance; it exceeds it only where a triangle's region of
///    closest points is too thin for the grid to carry it. Measured against exact distances:
///    at most 0.014 spacings on dino.off and 0.026 on ChineseDragon-10kv.off at 64 cells,
///    0.036 on bunny00.off at 128 cells and 0.023 at 256 (20,000 sampled nodes each), with
///    mean errors of 3e-5 to 5e-4 spacings, and 71–73% of bunny00.off's fill nodes exact to
///    1e-6 spacings.
/// 3. Sides beyond the band: the nodes there form regions that cannot cross the surface; each
///    region takes the side most of its nodes got from the band through the sweeps, so one
///    wrongly signed band node (next to a self-intersection, say) cannot spread.
///
/// A mesh that is not closed, or self-intersects, gets a field whose signs follow the
/// pseudonormals near the surface and are otherwise arbitrary where inside is undefined; use
/// polygon_soup_field() for such input.
/// @throws MeshError for an invalid mesh (validate()), one without triangles, or more than
///         2²⁷ − 1 triangles; Error for invalid options (cells, box_expansion, geometry,
///         exact_band < √3, memory_budget_bytes ≤ 0) or a grid above the memory budget;
///         Cancelled.
KHZ_CONTACT_API DistanceGrid signed_distance_field(const TriangleMesh& closed_mesh,
                                                   const DistanceFieldOptions& options = {});

/// The unsigned distance field of any triangle set (a polygon soup: open, non-manifold,
/// inconsistently oriented, self-intersecting): steps 1 and 2 of signed_distance_field(), with
/// the same accuracy. Same errors as signed_distance_field().
KHZ_CONTACT_API DistanceGrid unsigned_distance_field(const TriangleMesh& mesh,
                                                     const DistanceFieldOptions& options = {});

}  // namespace khz::contact
