#pragma once
// Pointshells sampled directly from a triangle mesh: the "alternative" generators of thesis
// §3.8.2 — mesh vertices, area-weighted random samples, voxel centres (VPS) — each point with
// the inward pseudonormal of its closest mesh feature. They come as one flat level; order them
// into nested levels with nested_pointshell() (§3.9.1).

#include <khz/contact/common.hpp>
#include <khz/contact/export.hpp>
#include <khz/contact/pointshell/pointshell.hpp>

#include <Eigen/Core>

#include <cstdint>

namespace khz::contact {

class MeshDistance;

/// The vertices of a triangle mesh as a one-level pointshell (§3.8.2: uniform only as far as
/// the mesh's vertices are). Vertices at exactly the same position are merged (an unwelded
/// mesh, e.g. from STL, gives the same pointshell as the welded one); vertices in no triangle are
/// left out. Points are in order of their lowest vertex index.
///
/// Each normal is the inward angle-weighted pseudonormal of the vertex [Bærentzen & Aanæs 2005]
/// — the vertex is its own closest feature — i.e. minus the sum over the vertex's non-degenerate
/// triangles of (incident angle × unit face normal), normalized: independent of how the faces
/// around the vertex are triangulated, and exact on sharp corners (a cube corner gets the
/// diagonal). Inward for a closed mesh with counter-clockwise triangles seen from outside.
/// Serial, O(#F + #V log #V).
/// @throws MeshError if the mesh fails validate() or has no triangles, or a vertex's triangles
///         are all degenerate (no normal), naming it.
KHZ_CONTACT_API Pointshell vertex_pointshell(const TriangleMesh& mesh);

/// `count` points drawn independently and uniformly by area from the surface (§3.8.2; the
/// starting distribution of particle repulsion, §3.8.1), as a one-level pointshell. A point lies
/// on the triangle it was drawn from, and its normal is that triangle's inward unit normal (the
/// face is the point's closest feature, except on a set of zero area: its edges).
///
/// Reproducible: point k depends only on (seed, k) and the mesh — the same random numbers on
/// every platform (counter-based SplitMix64 streams, not <random>'s implementation-defined
/// distributions) and the same point bit for bit for any thread count; builds for different
/// CPUs may round the areas and coordinates made from them differently in the last bits.
/// In parallel (OpenMP).
/// @param count Points wanted, ≥ 1.
/// @throws MeshError if the mesh fails validate(); Error if count < 1 or the mesh has zero total
///         area.
KHZ_CONTACT_API Pointshell random_pointshell(const TriangleMesh& mesh, Eigen::Index count,
                                             std::uint64_t seed = 0);

/// The classical Voxmap-PointShell pointshell (§3.1, §3.8.2): the centres of the cubic cells of
/// side `cell_size` whose closed box touches a triangle, as a one-level pointshell, in grid order
/// (x fastest). The centres are NOT moved onto the surface, as in VPS: they lie within
/// cell_size·√3/2 of it, on both sides, and where a cell face coincides with the surface both
/// cells touching it contribute (the "two layers" of §3.8.2). The grid is the cube of
/// reduced::voxelize() centred on the triangles' bounding box, its resolution the smallest that
/// covers the box with cells of (up to rounding) the given size. Normals from inward_normals().
/// @param cell_size Cell side (m), > 0; at most 1024 cells along the box's longest side.
/// @param progress Reports stage "pointshell normals".
/// @throws MeshError if the mesh fails validate() or has no triangles; Error if cell_size is not
///         positive and finite or too small for 1024 cells, or the vertices all coincide;
///         Cancelled.
KHZ_CONTACT_API Pointshell voxel_pointshell(const TriangleMesh& mesh, double cell_size,
                                            const ProgressCallback& progress = {});

/// Inward unit normals for arbitrary points (e.g. particle-repulsion points, §3.8.1): minus the
/// angle-weighted pseudonormal of the feature (face, edge or vertex) of `surface` closest to each
/// point (§3.8.1, [Bærentzen & Aanæs 2005]), as MeshDistance::closest() reports it. In parallel
/// (OpenMP).
/// @param points #P×3 positions (m).
/// @param progress Reports stage "pointshell normals" (units: points).
/// @returns #P×3 unit normals.
/// @throws Error if a point is not finite (naming it); Cancelled.
KHZ_CONTACT_API PointMatrix inward_normals(const MeshDistance& surface,
                                           const Eigen::Ref<const PointMatrix>& points,
                                           const ProgressCallback& progress = {});

}  // namespace khz::contact
