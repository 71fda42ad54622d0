// `mpirun -np 2`: MUMPS's factorization distributed over the ranks solves as CHOLMOD does on
// one process, and modal derivatives computed with it equal one process's (issue 24, item 3).
#include <khz/mpi/mpi_work_group.hpp>
#include <khz/mpi/mumps_factorization.hpp>
#include <khz/reduced/basis/linear_modes.hpp>
#include <khz/reduced/basis/modal_derivatives.hpp>
#include <khz/reduced/errors.hpp>
#include <khz/reduced/fem/fem_model.hpp>
#include <khz/reduced/meshing/box_mesh.hpp>
#include <khz/reduced/solvers/fixed_dofs.hpp>
#include <khz/reduced/solvers/sparse_cholesky.hpp>

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace khz::reduced {
namespace {

/// K(0) on all dofs.
SparseMatrix rest_stiffness(const FemModel& model) {
  SparseMatrix stiffness = model.stiffness_pattern();
  model.tangent_stiffness(Eigen::VectorXd::Zero(model.num_dofs()), stiffness);
  return stiffness;
}

FemModel bar() {
  return FemModel(box_tet_mesh(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1.0, 0.3, 0.2),
                               Eigen::Vector3i(10, 3, 3)),
                  {Material::stvk(1e6, 0.3, 1000.0)});
}

std::vector<int> clamped_end(const FemModel& model) {
  return vertices_in_box(model.mesh().vertices, Eigen::AlignedBox3d(Eigen::Vector3d(-1e-9, -1, -1),
                                                                    Eigen::Vector3d(1e-9, 1, 1)));
}

TEST(MpiMumpsFactorization, SolvesAsCholmodDoesOnOneProcess) {
  const FemModel model = bar();
  const FixedDofs dofs(model.mesh().vertices.rows(), clamped_end(model));
  const SparseMatrix stiffness = dofs.restrict_matrix(rest_stiffness(model));
  const Eigen::MatrixXd rhs = Eigen::MatrixXd::Random(stiffness.rows(), 7);
  SparseCholesky cholesky;
  cholesky.factorize(stiffness);
  const Eigen::MatrixXd reference = cholesky.solve(rhs);

  mpi::MumpsFactorization mumps(stiffness);
  EXPECT_TRUE(mumps.collective());
  const Eigen::MatrixXd solution = mumps.solve(rhs);  // rank 0's right-hand sides
  EXPECT_LT((solution - reference).norm() / reference.norm(), 1e-10);
  EXPECT_EQ(mumps.solve(Eigen::MatrixXd(stiffness.rows(), 0)).cols(), 0);
}

TEST(MpiMumpsFactorization, ASingularMatrixFailsOnEveryRank) {
  const FemModel model = bar();  // nothing fixed: K has the six rigid motions in its kernel
  const SparseMatrix stiffness = rest_stiffness(model);
  try {
    mpi::MumpsFactorization mumps(stiffness);
    ADD_FAILURE() << "factorized a singular matrix";
  } catch (const SolverError& error) {
    EXPECT_NE(std::string(error.what()).find("the matrix is singular"), std::string::npos)
        << error.what();
  }
}

double largest_relative_difference(const ModalDerivatives& a, const ModalDerivatives& b) {
  double worst = 0.0;
  for (Eigen::Index c = 0; c < b.vectors.cols(); ++c) {
    worst = std::max(worst, (a.vectors.col(c) - b.vectors.col(c)).norm() / b.vectors.col(c).norm());
  }
  return worst;
}

/// Modal derivatives with the factor distributed by MUMPS against CHOLMOD on this process.
double mumps_against_alone(bool anchored) {
  const FemModel model = bar();
  LinearModesOptions mode_options;
  mode_options.num_modes = 6;
  const LinearModes modes =
      compute_linear_modes(model, anchored ? clamped_end(model) : std::vector<int>{}, mode_options);
  ModalDerivativesOptions options;
  options.block_size = 5;
  const ModalDerivatives alone = compute_modal_derivatives(model, modes, options);
  mpi::MpiWorkGroup group;
  options.group = &group;
  options.factorize = mpi::MumpsFactorization::factorize();
  const ModalDerivatives distributed = compute_modal_derivatives(model, modes, options);
  EXPECT_EQ(distributed.pairs, alone.pairs);
  return largest_relative_difference(distributed, alone);
}

TEST(MpiMumpsFactorization, AnchoredModalDerivativesEqualOneProcessToTheFactorsRoundOff) {
  EXPECT_LT(mumps_against_alone(true), 1e-9);
}

TEST(MpiMumpsFactorization, FreeModalDerivativesEqualOneProcessWithinTheSolverTolerance) {
  EXPECT_LT(mumps_against_alone(false), 1e-6);
}

}  // namespace
}  // namespace khz::reduced
