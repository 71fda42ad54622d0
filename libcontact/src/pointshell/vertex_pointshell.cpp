#include <khz/contact/pointshell/pointshell_sampling.hpp>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>
#include <vector>

namespace khz::contact {

namespace {

/// For every vertex, the index of the lowest-numbered vertex at exactly its position.
std::vector<Eigen::Index> welded_vertices(const PointMatrix& vertices) {
  std::vector<Eigen::Index> sorted(static_cast<std::size_t>(vertices.rows()));
  std::iota(sorted.begin(), sorted.end(), Eigen::Index{0});
  const auto lexicographic = [&](Eigen::Index a, Eigen::Index b) {
    for (int k = 0; k < 3; ++k) {
      if (vertices(a, k) != vertices(b, k)) return vertices(a, k) < vertices(b, k);
    }
    return a < b;
  };
  std::sort(sorted.begin(), sorted.end(), lexicographic);
  std::vector<Eigen::Index> representative(sorted.size());
  for (std::size_t i = 0; i < sorted.size(); ++i) {
    const bool same = i > 0 && vertices.row(sorted[i]) == vertices.row(sorted[i - 1]);
    // Sorted by index among equals: the first of a run is the lowest index.
    representative[static_cast<std::size_t>(sorted[i])] =
        same ? representative[static_cast<std::size_t>(sorted[i - 1])] : sorted[i];
  }
  return representative;
}

}  // namespace

Pointshell vertex_pointshell(const TriangleMesh& mesh) {
  validate(mesh);
  if (mesh.num_triangles() == 0) throw MeshError("vertex_pointshell: the mesh has no triangles");
  const std::vector<Eigen::Index> weld = welded_vertices(mesh.vertices);

  // Σ angle × unit face normal at every (welded) vertex; `used` marks vertices in a triangle.
  PointMatrix sums = PointMatrix::Zero(mesh.num_vertices(), 3);
  std::vector<char> used(static_cast<std::size_t>(mesh.num_vertices()), 0);
  for (Eigen::Index t = 0; t < mesh.num_triangles(); ++t) {
    Eigen::Index v[3];
    Eigen::Vector3d x[3];
    for (int k = 0; k < 3; ++k) {
      v[k] = weld[static_cast<std::size_t>(mesh.triangles(t, k))];
      x[k] = mesh.vertices.row(v[k]).transpose();
      used[static_cast<std::size_t>(v[k])] = 1;
    }
    const Eigen::Vector3d cross = (x[1] - x[0]).cross(x[2] - x[0]);
    const double length = cross.norm();
    if (!(length > 0.0)) continue;  // degenerate: no normal, no angle
    const Eigen::Vector3d face_normal = cross / length;
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d e1 = x[(k + 1) % 3] - x[k];
      const Eigen::Vector3d e2 = x[(k + 2) % 3] - x[k];
      // atan2 of |e1×e2| and e1·e2: accurate for angles near 0 and π, unlike acos.
      const double angle = std::atan2(e1.cross(e2).norm(), e1.dot(e2));
      sums.row(v[k]) += angle * face_normal.transpose();
    }
  }

  Pointshell pointshell;
  const auto count = static_cast<Eigen::Index>(std::count(used.begin(), used.end(), 1));
  pointshell.points.resize(count, 3);
  pointshell.normals.resize(count, 3);
  Eigen::Index s = 0;
  for (Eigen::Index v = 0; v < mesh.num_vertices(); ++v) {
    if (!used[static_cast<std::size_t>(v)]) continue;
    const double length = sums.row(v).norm();
    if (!(length > 0.0)) {
      throw MeshError("vertex_pointshell: vertex " + std::to_string(v) +
                      " has no normal (its triangles are degenerate or cancel out)");
    }
    pointshell.points.row(s) = mesh.vertices.row(v);
    pointshell.normals.row(s) = -sums.row(v) / length;  // inward (§3.5)
    ++s;
  }
  pointshell.level_ends = {count};
  return pointshell;
}

}  // namespace khz::contact
