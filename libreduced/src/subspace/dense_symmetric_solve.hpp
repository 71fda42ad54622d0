#pragma once
// Allocation-free solve of a dense symmetric r×r system: Cholesky (LDLᵀ), and a pseudo-inverse
// through the eigendecomposition when the matrix is not positive definite.

#include <Eigen/Core>
#include <Eigen/Eigenvalues>

namespace khz::reduced::detail {

/// How DenseSymmetricSolver::solve_in_place() solved a system, or that it could not.
enum class DenseSolve {
  cholesky,        ///< A was positive definite: x = A⁻¹ b by LDLᵀ (square-root-free Cholesky).
  eigen_fallback,  ///< A was not: x = A⁺ b through A = V Λ Vᵀ.
  failed,          ///< A or b not finite, the eigen iteration did not converge, or x overflowed.
};

/// Solves A x = b for a symmetric r×r matrix A (only its lower triangle is read) with every
/// workspace allocated in the constructor: the reduced integrators call it inside a time step.
///
/// Cholesky first, as LDLᵀ in chunks of SIMD lanes: at r ≤ 60 that beats Eigen's LLT, whose
/// per-column kernel calls cost more than the arithmetic. When A is not positive definite (a pivot
/// ≤ 0, e.g. a tangent stiffness so negative that it beats the inertia term), x = V Λ⁺ Vᵀ b from
/// the symmetric eigendecomposition A = V Λ Vᵀ with the true, signed eigenvalues, where |λ| ≤
/// 1e-12·max|λ| counts as zero: the pseudo-inverse, i.e. the minimum-norm least-squares solution,
/// which stays finite when A is singular (an indefinite Newton direction is then still the exact
/// solution wherever A is invertible). Eigen's SelfAdjointEigenSolver::compute() allocates a
/// Householder workspace when it forms eigenvectors, so the fallback runs its pieces itself:
/// Householder tridiagonalization A = Q T Qᵀ in place, SelfAdjointEigenSolver's QL iteration on the
/// tridiagonal T = W Λ Wᵀ, and x = Q W Λ⁺ Wᵀ Qᵀ b with the reflectors of Q applied to vectors.
class DenseSymmetricSolver {
 public:
  /// Workspaces for r = `size` (≥ 1).
  explicit DenseSymmetricSolver(Eigen::Index size);

  /// Replaces b (in `rhs_and_solution`, r entries) by x for `matrix` (r×r). On failed the vector
  /// holds unspecified values. Allocates nothing.
  DenseSolve solve_in_place(const Eigen::MatrixXd& matrix,
                            Eigen::VectorXd& rhs_and_solution) noexcept;

 private:
  /// m_factor ← A = LDLᵀ (L unit lower) and y = L⁻¹ b; false when a pivot is not positive (or
  /// NaN), i.e. A is not positive definite.
  bool factor_ldlt(const Eigen::MatrixXd& matrix, const Eigen::VectorXd& rhs) noexcept;
  /// x ← L⁻ᵀ D⁻¹ y from m_factor.
  void back_substitute(Eigen::VectorXd& x) const noexcept;
  bool solve_by_eigendecomposition(const Eigen::MatrixXd& matrix, Eigen::VectorXd& x) noexcept;
  /// x ← H_k x with H_k = I − h_k v_k v_kᵀ, the k-th reflector of the tridiagonalization.
  void apply_reflector(Eigen::Index k, Eigen::VectorXd& x) const noexcept;

  Eigen::MatrixXd m_factor;             // LD below the diagonal, Lᵀ above, yᵀ in row r, padding
  Eigen::VectorXd m_inverse_pivots;     // 1 / d_j
  Eigen::MatrixXd m_packed;             // tridiagonalized copy of A: T and the reflectors v_k
  Eigen::VectorXd m_householder;        // h_k, r − 1 entries
  Eigen::VectorXd m_diagonal;           // of T
  Eigen::VectorXd m_subdiagonal;        // of T
  Eigen::VectorXd m_eigen_coordinates;  // Wᵀ Qᵀ b, then Λ⁺ Wᵀ Qᵀ b
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> m_tridiagonal_eigen;
};

}  // namespace khz::reduced::detail
