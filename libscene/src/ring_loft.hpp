#pragma once
// Closed surfaces lofted through rings of points: the procedural shapes' common construction.
//
// `rings` holds the rings one after the other, each `ring_size` points (row i·ring_size + j is
// point j of ring i). Point j of each ring is joined to point j of the next, and each quad so
// made is split into two triangles. The triangles face outwards when every ring runs (j → j + 1)
// along d × n, d pointing to the next ring and n outwards: counter-clockwise about d, by the
// right-hand rule, for a tube.

#include <khz/reduced/mesh/triangle_mesh.hpp>

#include <Eigen/Core>

namespace khz::scene::detail {

/// The rings joined in order, with the first closed by a fan to `first_pole` and the last by a
/// fan to `last_pole` (a sphere-like surface). Precondition: ring_size ≥ 3, rings.rows() a
/// positive multiple of it.
reduced::TriangleMesh loft_between_poles(const reduced::VertexMatrix& rings, int ring_size,
                                         const Eigen::RowVector3d& first_pole,
                                         const Eigen::RowVector3d& last_pole);

/// The rings joined in order and the last joined back to the first (a torus-like surface).
/// Precondition: ring_size ≥ 3, rings.rows() at least three times it and a multiple of it.
reduced::TriangleMesh loft_cyclic(const reduced::VertexMatrix& rings, int ring_size);

/// The corners of the square [−half, half]² at height z, counter-clockwise seen from +z.
Eigen::Matrix<double, 4, 3, Eigen::RowMajor> square_ring(double half, double z);

}  // namespace khz::scene::detail
