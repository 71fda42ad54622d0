#pragma once
// Structured volume meshes of an axis-aligned box: test geometry and simple simulation models.

#include <khz/reduced/export.hpp>
#include <khz/reduced/mesh/volume_mesh.hpp>

#include <Eigen/Core>

namespace khz::reduced {

/// A box [min_corner, max_corner] divided into cells.x()×cells.y()×cells.z() equal cells,
/// one trilinear hexahedron per cell, in VTK node order and positively oriented.
///
/// Vertex numbering (relied on by callers that pick vertices, e.g. the x = min face to clamp a
/// cantilever): lattice point (i, j, k), 0 ≤ i ≤ cells.x() etc., has index
/// i + (cells.x()+1)·(j + (cells.y()+1)·k) — x fastest, then y, then z — and position
/// min_corner + (i·hx, j·hy, k·hz) with h = (max_corner − min_corner) / cells. Cell (i, j, k)
/// is element i + cells.x()·(j + cells.y()·k), its node 0 is lattice point (i, j, k).
/// element_groups is empty. Units are those of the corners.
/// @throws Error if a cell count is < 1, a corner is not finite, or min_corner is not below
///         max_corner in every coordinate.
KHZ_REDUCED_API VolumeMesh box_hex_mesh(const Eigen::Vector3d& min_corner,
                                        const Eigen::Vector3d& max_corner,
                                        const Eigen::Vector3i& cells);

/// The same box, vertices and vertex numbering as box_hex_mesh(), with every cell split into six
/// positively oriented tetrahedra around its diagonal from lattice point (i, j, k) to
/// (i+1, j+1, k+1) (the Kuhn / Freudenthal split). Every cell is split the same way, so the
/// faces of neighbouring cells conform and the mesh has no hanging edges. Cell c's tetrahedra
/// are elements 6c … 6c+5. element_groups is empty.
/// @throws Error under the same conditions as box_hex_mesh().
KHZ_REDUCED_API VolumeMesh box_tet_mesh(const Eigen::Vector3d& min_corner,
                                        const Eigen::Vector3d& max_corner,
                                        const Eigen::Vector3i& cells);

}  // namespace khz::reduced
