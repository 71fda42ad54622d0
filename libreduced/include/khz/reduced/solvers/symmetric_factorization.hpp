#pragma once
// The factorization a precomputation solves with, as an interface, so that a program can put a
// factorization of its own behind it: khz::mpi::MumpsFactorization distributes the factor over
// the ranks of an MPI job, for meshes whose factor does not fit one node (issue 24).

#include <khz/reduced/export.hpp>
#include <khz/reduced/fem/fem_model.hpp>

#include <Eigen/Core>

#include <functional>
#include <memory>

namespace khz::reduced {

/// A factorization of a sparse symmetric positive definite n × n matrix A, ready to solve.
class KHZ_REDUCED_API SymmetricFactorization {
 public:
  virtual ~SymmetricFactorization();

  /// X = A⁻¹ B, B and X n × m. Not thread-safe (a factorization may keep a workspace).
  /// @throws SolverError if the solve fails; Error if B has not n rows.
  virtual Eigen::MatrixXd solve(const Eigen::MatrixXd& rhs) = 0;

  /// false: this process solves alone. true: the factor is distributed over a group of
  /// processes, each of which must call solve() at the same time with the same right-hand
  /// sides (each gets the whole solution); a computation given such a factorization solves
  /// every right-hand side on every process of the group.
  virtual bool collective() const noexcept { return false; }
};

/// Makes a SymmetricFactorization of A (both triangles given, A symmetric).
/// @throws SolverError if A is not positive definite.
using Factorize = std::function<std::unique_ptr<SymmetricFactorization>(const SparseMatrix& a)>;

}  // namespace khz::reduced
