#pragma once
// The subject of the shared modal-derivative tests (threads standing in for ranks, and under
// mpiexec): a small bar and its linear modes, and how far two sets of derivatives are apart.

#include <khz/reduced/basis/linear_modes.hpp>
#include <khz/reduced/fem/fem_model.hpp>
#include <khz/reduced/meshing/box_mesh.hpp>
#include <khz/reduced/solvers/fixed_dofs.hpp>

#include <Eigen/Core>

#include <algorithm>
#include <vector>

namespace khz::test {

/// A 1 × 0.3 × 0.2 bar of 10 × 3 × 3 cells of tetrahedra (distinct sides: simple eigenvalues),
/// clamped at x = 0 or free, with its first 6 linear modes.
struct DerivativeBar {
  explicit DerivativeBar(bool anchored)
      : model(reduced::box_tet_mesh(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1.0, 0.3, 0.2),
                                    Eigen::Vector3i(10, 3, 3)),
              {reduced::Material::stvk(1e6, 0.3, 1000.0)}) {
    if (anchored) {
      fixed = reduced::vertices_in_box(
          model.mesh().vertices,
          Eigen::AlignedBox3d(Eigen::Vector3d(-1e-9, -1, -1), Eigen::Vector3d(1e-9, 1, 1)));
    }
    reduced::LinearModesOptions options;
    options.num_modes = 6;
    modes = reduced::compute_linear_modes(model, fixed, options);
  }
  reduced::FemModel model;
  std::vector<int> fixed;
  reduced::LinearModes modes;
};

/// The largest ‖aᵢ − bᵢ‖ / ‖bᵢ‖ over the columns i.
inline double largest_column_difference(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  double worst = 0.0;
  for (Eigen::Index c = 0; c < b.cols(); ++c) {
    worst = std::max(worst, (a.col(c) - b.col(c)).norm() / b.col(c).norm());
  }
  return worst;
}

}  // namespace khz::test
