#pragma once
// Displacement vectors as VTK point arrays, for the examples' ParaView output.

#include <Eigen/Core>

namespace khz::examples {

/// A 3n displacement vector (dof 3v+i is vertex v's axis i) as an n×3 point array.
inline Eigen::MatrixXd per_vertex(const Eigen::VectorXd& u) {
  return Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>>(
      u.data(), u.size() / 3, 3);
}

}  // namespace khz::examples
