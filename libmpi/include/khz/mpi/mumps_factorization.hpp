#pragma once
// A sparse symmetric positive definite factorization whose factor is distributed over the ranks
// of an MPI communicator, by MUMPS (Debian libmumps-dev): for modal derivatives of meshes whose
// factor does not fit the memory of one node (issue 24, item 3).

#include <khz/mpi/export.hpp>
#include <khz/reduced/solvers/symmetric_factorization.hpp>

#include <mpi.h>

#include <memory>

namespace khz::mpi {

/// A = L D Lᵀ of a symmetric positive definite A, the factor spread over the ranks of
/// `communicator`: MUMPS's symmetric factorization (SYM = 2, with its threshold pivoting, the
/// one whose null-pivot detection works, so a singular A is refused as SparseCholesky refuses
/// it) and its own ordering. Rank 0 gives the matrix (the others' copies are not read) and the
/// right-hand sides; every rank receives the whole solution. Every method is collective: every
/// rank of the communicator calls it, in the same order, from the thread that initialized
/// MPI.
///
/// Why MUMPS and not PETSc: the precomputation needs one thing distributed, a direct
/// factorization with many right-hand sides; MUMPS is that library with a 60-field C struct
/// and nothing else to set up, while PETSc would bring its own object system, option database
/// and build for the same solver (PETSc's own direct Cholesky is serial; it calls MUMPS for a
/// distributed one). Linear modes stay on ARPACK per process.
class KHZ_MPI_API MumpsFactorization final : public reduced::SymmetricFactorization {
 public:
  /// Collective: analyses and factorizes `a` (n × n, both triangles, symmetric positive
  /// definite; the lower triangle of rank 0's copy is used).
  /// @throws reduced::SolverError on every rank: "the matrix is singular" when MUMPS finds
  ///         pivots below n·ε·‖A‖ (its null-pivot detection, ICNTL(24), as SparseCholesky
  ///         refuses a pivot ratio below n·ε), or naming MUMPS's INFOG(1) and INFOG(2) (e.g.
  ///         -9 / -13: out of memory).
  explicit MumpsFactorization(const reduced::SparseMatrix& a,
                              MPI_Comm communicator = MPI_COMM_WORLD);
  ~MumpsFactorization() override;
  MumpsFactorization(const MumpsFactorization&) = delete;
  MumpsFactorization& operator=(const MumpsFactorization&) = delete;

  /// Collective: X = A⁻¹ B. Rank 0's B is used (n × m); every rank returns X.
  /// @throws reduced::Error if rank 0's B has not n rows; reduced::SolverError if MUMPS fails.
  Eigen::MatrixXd solve(const Eigen::MatrixXd& rhs) override;
  bool collective() const noexcept override { return true; }

  /// A reduced::Factorize that makes a MumpsFactorization over `communicator`, for
  /// ModalDerivativesOptions::factorize.
  static reduced::Factorize factorize(MPI_Comm communicator = MPI_COMM_WORLD);

 private:
  struct Mumps;
  std::unique_ptr<Mumps> m_mumps;
};

}  // namespace khz::mpi
