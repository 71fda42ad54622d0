#pragma once
// Defect detection shared by analyze_mesh() and the repair operations, so that what the report
// flags is exactly what the repairs remove.

#include <khz/reduced/mesh/triangle_mesh.hpp>

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <numeric>
#include <vector>

namespace khz::reduced::detail {

/// Bounding box of the vertices some triangle uses; empty when there is none.
inline Eigen::AlignedBox3d referenced_bounding_box(const TriangleMesh& mesh) {
  Eigen::AlignedBox3d box;
  for (Eigen::Index t = 0; t < mesh.num_triangles(); ++t) {
    for (int k = 0; k < 3; ++k) box.extend(mesh.vertices.row(mesh.triangles(t, k)).transpose());
  }
  return box;
}

/// True if triangle `t` uses a vertex twice: it then has no three edges, so topology ignores it.
inline bool has_repeated_vertex(const TriangleMesh& mesh, Eigen::Index t) {
  const auto tri = mesh.triangles.row(t);
  return tri(0) == tri(1) || tri(1) == tri(2) || tri(2) == tri(0);
}

/// Per triangle: true if it repeats a vertex or its area vanishes relative to the mesh size
/// (|(b−a)×(c−a)| ≤ 1e-12·diagonal², `box` being referenced_bounding_box()).
inline std::vector<bool> degenerate_triangle_mask(const TriangleMesh& mesh,
                                                  const Eigen::AlignedBox3d& box) {
  // Relative to the squared diagonal so the test does not depend on the length unit.
  const double threshold = box.isEmpty() ? 0.0 : 1e-12 * box.diagonal().squaredNorm();
  std::vector<bool> degenerate(mesh.num_triangles());
  for (Eigen::Index t = 0; t < mesh.num_triangles(); ++t) {
    if (has_repeated_vertex(mesh, t)) {
      degenerate[t] = true;
      continue;
    }
    const auto tri = mesh.triangles.row(t);
    const Eigen::Vector3d a = mesh.vertices.row(tri(0));
    const Eigen::Vector3d b = mesh.vertices.row(tri(1));
    const Eigen::Vector3d c = mesh.vertices.row(tri(2));
    degenerate[t] = (b - a).cross(c - a).norm() <= threshold;
  }
  return degenerate;
}

/// Sorted indices of the triangles with three distinct vertices that use the same vertices (in
/// any order) as a lower-indexed triangle.
inline std::vector<Eigen::Index> duplicate_triangles(const TriangleMesh& mesh) {
  struct Keyed {
    std::array<int, 3> vertices;  // sorted, so any vertex order compares equal
    Eigen::Index triangle;
    auto operator<=>(const Keyed&) const = default;
  };
  std::vector<Keyed> keyed;
  keyed.reserve(mesh.num_triangles());
  for (Eigen::Index t = 0; t < mesh.num_triangles(); ++t) {
    if (has_repeated_vertex(mesh, t)) continue;
    Keyed entry{{mesh.triangles(t, 0), mesh.triangles(t, 1), mesh.triangles(t, 2)}, t};
    std::sort(entry.vertices.begin(), entry.vertices.end());
    keyed.push_back(entry);
  }
  std::sort(keyed.begin(), keyed.end());
  std::vector<Eigen::Index> duplicates;
  for (std::size_t i = 1; i < keyed.size(); ++i) {
    if (keyed[i].vertices == keyed[i - 1].vertices) duplicates.push_back(keyed[i].triangle);
  }
  std::sort(duplicates.begin(), duplicates.end());
  return duplicates;
}

/// For each vertex, the lowest-indexed vertex with exactly the same position (itself when
/// there is none). O(V log V): rows are sorted lexicographically, ties by index.
inline std::vector<Eigen::Index> exact_duplicate_representatives(const VertexMatrix& vertices) {
  const auto same = [&](Eigen::Index a, Eigen::Index b) {
    return (vertices.row(a).array() == vertices.row(b).array()).all();
  };
  std::vector<Eigen::Index> order(vertices.rows());
  std::iota(order.begin(), order.end(), Eigen::Index{0});
  std::sort(order.begin(), order.end(), [&](Eigen::Index a, Eigen::Index b) {
    for (int c = 0; c < 3; ++c) {
      if (vertices(a, c) != vertices(b, c)) return vertices(a, c) < vertices(b, c);
    }
    return a < b;
  });
  std::vector<Eigen::Index> representative(vertices.rows());
  for (std::size_t i = 0; i < order.size(); ++i) {
    const bool starts_group = i == 0 || !same(order[i - 1], order[i]);
    representative[order[i]] = starts_group ? order[i] : representative[order[i - 1]];
  }
  return representative;
}

}  // namespace khz::reduced::detail
