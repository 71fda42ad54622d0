// `mpirun -np 2`: modal derivatives shared over the ranks equal one process's, on every rank
// (anchored: to round-off; free: within MINRES's tolerance).
#include <khz/mpi/mpi_work_group.hpp>
#include <khz/reduced/basis/linear_modes.hpp>
#include <khz/reduced/basis/modal_derivatives.hpp>
#include <khz/reduced/fem/fem_model.hpp>
#include <khz/reduced/meshing/box_mesh.hpp>
#include <khz/reduced/solvers/fixed_dofs.hpp>

#include <gtest/gtest.h>

#include <vector>

namespace khz::reduced {
namespace {

double largest_relative_difference(const ModalDerivatives& a, const ModalDerivatives& b) {
  double worst = 0.0;
  for (Eigen::Index c = 0; c < b.vectors.cols(); ++c) {
    worst = std::max(worst, (a.vectors.col(c) - b.vectors.col(c)).norm() / b.vectors.col(c).norm());
  }
  return worst;
}

/// Shared over MPI_COMM_WORLD against this process alone, for a 1 × 0.3 × 0.2 bar clamped at
/// x = 0 or free.
double shared_against_alone(bool anchored) {
  const FemModel model(box_tet_mesh(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1.0, 0.3, 0.2),
                                    Eigen::Vector3i(10, 3, 3)),
                       {Material::stvk(1e6, 0.3, 1000.0)});
  std::vector<int> fixed;
  if (anchored) {
    fixed = vertices_in_box(
        model.mesh().vertices,
        Eigen::AlignedBox3d(Eigen::Vector3d(-1e-9, -1, -1), Eigen::Vector3d(1e-9, 1, 1)));
  }
  LinearModesOptions mode_options;
  mode_options.num_modes = 6;
  const LinearModes modes = compute_linear_modes(model, fixed, mode_options);
  ModalDerivativesOptions options;
  options.block_size = 5;  // blocks not aligned with the ranks' shares
  const ModalDerivatives alone = compute_modal_derivatives(model, modes, options);
  mpi::MpiWorkGroup group;
  options.group = &group;
  const ModalDerivatives shared = compute_modal_derivatives(model, modes, options);
  EXPECT_EQ(shared.pairs, alone.pairs);
  return largest_relative_difference(shared, alone);
}

TEST(MpiModalDerivatives, AnchoredEqualOneProcessToRoundOff) {
  EXPECT_LT(shared_against_alone(true), 1e-13);
}

TEST(MpiModalDerivatives, FreeEqualOneProcessWithinTheSolverTolerance) {
  EXPECT_LT(shared_against_alone(false), 1e-6);
}

}  // namespace
}  // namespace khz::reduced
