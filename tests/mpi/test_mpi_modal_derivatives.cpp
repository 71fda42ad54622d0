// `mpirun -np 2`: modal derivatives shared over the ranks equal one process's on every rank,
// with every rank factorizing on its own (CHOLMOD) or the factor distributed over the ranks
// (MUMPS): anchored to round-off, free within MINRES's tolerance.
#include <khz/mpi/mpi_work_group.hpp>
#include <khz/mpi/mumps_factorization.hpp>
#include <khz/reduced/basis/modal_derivatives.hpp>
#include <khz/test/derivative_bar.hpp>

#include <gtest/gtest.h>

namespace khz::reduced {
namespace {

/// Shared over MPI_COMM_WORLD (with `factorize`) against this process alone (CHOLMOD).
double shared_against_alone(bool anchored, const Factorize& factorize) {
  const test::DerivativeBar bar(anchored);
  ModalDerivativesOptions options;
  options.block_size = 5;  // blocks not aligned with the ranks' shares
  const ModalDerivatives alone = compute_modal_derivatives(bar.model, bar.modes, options);
  mpi::MpiWorkGroup group;
  options.group = &group;
  options.factorize = factorize;
  const ModalDerivatives shared = compute_modal_derivatives(bar.model, bar.modes, options);
  EXPECT_EQ(shared.pairs, alone.pairs);
  return test::largest_column_difference(shared.vectors, alone.vectors);
}

TEST(MpiModalDerivatives, AnchoredEqualOneProcessToRoundOff) {
  EXPECT_LT(shared_against_alone(true, {}), 1e-13);
}

TEST(MpiModalDerivatives, FreeEqualOneProcessWithinTheSolverTolerance) {
  EXPECT_LT(shared_against_alone(false, {}), 1e-6);
}

TEST(MpiModalDerivatives, AnchoredWithTheFactorDistributedByMumpsEqualOneProcess) {
  // Another factorization (LDLᵀ with pivoting, against CHOLMOD's LLᵀ): its own round-off.
  EXPECT_LT(shared_against_alone(true, mpi::MumpsFactorization::factorize()), 1e-9);
}

TEST(MpiModalDerivatives, FreeWithTheFactorDistributedByMumpsEqualOneProcess) {
  EXPECT_LT(shared_against_alone(false, mpi::MumpsFactorization::factorize()), 1e-6);
}

}  // namespace
}  // namespace khz::reduced
