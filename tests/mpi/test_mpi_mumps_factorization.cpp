// `mpirun -np 2`: MUMPS's factorization distributed over the ranks solves as CHOLMOD does on
// one process and refuses a singular matrix on every rank (issue 24, item 3; the modal
// derivatives computed with it: test_mpi_modal_derivatives.cpp).
#include <khz/mpi/mumps_factorization.hpp>
#include <khz/reduced/errors.hpp>
#include <khz/reduced/fem/fem_model.hpp>
#include <khz/reduced/solvers/fixed_dofs.hpp>
#include <khz/reduced/solvers/sparse_cholesky.hpp>
#include <khz/test/derivative_bar.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <string>

namespace khz::reduced {
namespace {

/// K(0) on all dofs.
SparseMatrix rest_stiffness(const FemModel& model) {
  SparseMatrix stiffness = model.stiffness_pattern();
  model.tangent_stiffness(Eigen::VectorXd::Zero(model.num_dofs()), stiffness);
  return stiffness;
}

TEST(MpiMumpsFactorization, SolvesAsCholmodDoesOnOneProcess) {
  const test::DerivativeBar bar(true);
  const FixedDofs dofs(bar.model.mesh().vertices.rows(), bar.fixed);
  const SparseMatrix stiffness = dofs.restrict_matrix(rest_stiffness(bar.model));
  // The same on every rank, though only rank 0's is read.
  const Eigen::MatrixXd rhs = Eigen::MatrixXd::NullaryExpr(
      stiffness.rows(), 7, [](Eigen::Index i, Eigen::Index j) { return std::sin(0.1 * i + j); });
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
  const test::DerivativeBar bar(false);  // nothing fixed: K has the rigid motions in its kernel
  const SparseMatrix stiffness = rest_stiffness(bar.model);
  try {
    mpi::MumpsFactorization mumps(stiffness);
    ADD_FAILURE() << "factorized a singular matrix";
  } catch (const SolverError& error) {
    EXPECT_NE(std::string(error.what()).find("the matrix is singular"), std::string::npos)
        << error.what();
  }
}

}  // namespace
}  // namespace khz::reduced
