#include <khz/reduced/subspace/vertex_normals.hpp>

#include "detail/size_check.hpp"
#include "mesh/mesh_checks.hpp"

#include <Eigen/Geometry>

namespace khz::reduced {

void vertex_normals(const Eigen::Ref<const VertexMatrix>& positions,
                    const Eigen::Ref<const TriangleMatrix>& triangles,
                    Eigen::Ref<VertexMatrix> normals) {
  const Eigen::Index count = positions.rows();
  detail::check_size("normals", "rows", normals.rows(), count, "one per vertex");
  detail::check_indices(triangles, count, "triangle");
  normals.setZero();
  for (Eigen::Index t = 0; t < triangles.rows(); ++t) {
    const Eigen::RowVector3d a = positions.row(triangles(t, 0));
    const Eigen::RowVector3d b = positions.row(triangles(t, 1));
    const Eigen::RowVector3d c = positions.row(triangles(t, 2));
    const Eigen::RowVector3d area_normal = (b - a).cross(c - a);
    for (int k = 0; k < 3; ++k) normals.row(triangles(t, k)) += area_normal;
  }
  for (Eigen::Index v = 0; v < count; ++v) {
    const double length = normals.row(v).norm();
    if (length > 0.0) normals.row(v) /= length;
  }
}

}  // namespace khz::reduced
