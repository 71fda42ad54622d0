#include "ring_loft.hpp"

namespace khz::scene::detail {
namespace {

/// Writes the 2·n triangles joining the rings starting at vertices `a` and `b` from row `row`
/// on; returns the row after them.
Eigen::Index join_rings(reduced::TriangleMatrix& triangles, Eigen::Index row, int a, int b, int n) {
  for (int j = 0; j < n; ++j) {
    const int k = (j + 1) % n;
    triangles.row(row++) << a + j, a + k, b + j;
    triangles.row(row++) << a + k, b + k, b + j;
  }
  return row;
}

}  // namespace

reduced::TriangleMesh loft_between_poles(const reduced::VertexMatrix& rings, int ring_size,
                                         const Eigen::RowVector3d& first_pole,
                                         const Eigen::RowVector3d& last_pole) {
  const int count = static_cast<int>(rings.rows()) / ring_size;
  const int first = count * ring_size;  // the poles' vertex indices
  const int last = first + 1;
  reduced::TriangleMesh mesh;
  mesh.vertices.resize(rings.rows() + 2, 3);
  mesh.vertices << rings, first_pole, last_pole;
  mesh.triangles.resize(2 * Eigen::Index{ring_size} * count, 3);
  Eigen::Index row = 0;
  for (int i = 0; i + 1 < count; ++i) {
    row = join_rings(mesh.triangles, row, i * ring_size, (i + 1) * ring_size, ring_size);
  }
  const int end = (count - 1) * ring_size;
  for (int j = 0; j < ring_size; ++j) {
    const int k = (j + 1) % ring_size;
    mesh.triangles.row(row++) << first, k, j;
    mesh.triangles.row(row++) << last, end + j, end + k;
  }
  return mesh;
}

reduced::TriangleMesh loft_cyclic(const reduced::VertexMatrix& rings, int ring_size) {
  const int count = static_cast<int>(rings.rows()) / ring_size;
  reduced::TriangleMesh mesh;
  mesh.vertices = rings;
  mesh.triangles.resize(2 * Eigen::Index{ring_size} * count, 3);
  Eigen::Index row = 0;
  for (int i = 0; i < count; ++i) {
    row = join_rings(mesh.triangles, row, i * ring_size, (i + 1) % count * ring_size, ring_size);
  }
  return mesh;
}

Eigen::Matrix<double, 4, 3, Eigen::RowMajor> square_ring(double half, double z) {
  Eigen::Matrix<double, 4, 3, Eigen::RowMajor> ring;
  ring << half, -half, z, half, half, z, -half, half, z, -half, -half, z;
  return ring;
}

}  // namespace khz::scene::detail
