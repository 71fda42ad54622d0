#pragma once
// The beam examples' vertex picking: a cantilever's clamped end, its tip, and where the tip moves.

#include <khz/reduced/mesh/triangle_mesh.hpp>
#include <khz/reduced/solvers/fixed_dofs.hpp>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <limits>
#include <span>
#include <vector>

namespace khz::examples {

/// The vertices on the plane x = `x` (within 1e-9, any y and z): a beam's clamped end or tip.
inline std::vector<int> vertices_at_x(const khz::reduced::VertexMatrix& vertices, double x) {
  const double far = std::numeric_limits<double>::max();
  return khz::reduced::vertices_in_box(vertices,
                                       Eigen::AlignedBox3d(Eigen::Vector3d(x - 1e-9, -far, -far),
                                                           Eigen::Vector3d(x + 1e-9, far, far)));
}

/// The mean over `vertices` of the three rows 3v … 3v+2 of a 3n×c matrix: of a displacement
/// (c = 1) the vertices' mean displacement; of a basis U (c = r) the 3×r map from q to it.
inline Eigen::MatrixXd vertex_mean(const Eigen::Ref<const Eigen::MatrixXd>& rows,
                                   std::span<const int> vertices) {
  Eigen::MatrixXd mean = Eigen::MatrixXd::Zero(3, rows.cols());
  for (int v : vertices) mean += rows.middleRows<3>(3 * v);
  return mean / static_cast<double>(vertices.size());
}

}  // namespace khz::examples
