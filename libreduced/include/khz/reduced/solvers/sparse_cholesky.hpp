#pragma once
// Sparse direct solver for the symmetric systems of the precomputation: Newton steps
// K(u) Δu = f − R(u) of static solves (thesis §2.1.10), modal derivatives (eq. 2.47) and the
// shift-inverted eigenproblems behind linear modes (§2.8.3).

#include <khz/reduced/export.hpp>
#include <khz/reduced/fem/fem_model.hpp>

#include <Eigen/Core>

#include <memory>

namespace khz::reduced {

/// Solves A x = b for a sparse symmetric matrix A by a Cholesky factorization with a
/// fill-reducing ordering (CHOLMOD: AMD, or METIS when CHOLMOD finds it better).
///
/// The work is split as in a Newton loop: analyze() the sparsity pattern once, then
/// factorize() each new matrix with that pattern and solve() any number of right-hand sides.
/// Matrices are passed whole (both triangles, as FemModel assembles them); only one triangle is
/// read, so A must be symmetric.
///
/// Not thread-safe, not even solve(): the object holds CHOLMOD's workspace. Use one per thread.
/// Moveable, not copyable; a moved-from object may only be destroyed or assigned to.
class KHZ_REDUCED_API SparseCholesky {
 public:
  enum class Kind {
    /// A = L Lᵀ (supernodal or simplicial, as CHOLMOD finds faster): A must be symmetric
    /// positive definite. The fast, stable choice for stiffness and mass matrices.
    llt,
    /// A = L D Lᵀ, simplicial, without pivoting: for symmetric indefinite but nonsingular A
    /// (e.g. K − σM in a shift-invert eigensolve). Fails on a zero pivot, which an indefinite
    /// matrix can have even when nonsingular (e.g. [[0, 1], [1, 0]]); no pivoting also means
    /// no guard against growth, so solutions for badly conditioned indefinite A may lose digits.
    ldlt,
  };

  explicit SparseCholesky(Kind kind = Kind::llt);
  ~SparseCholesky();
  SparseCholesky(SparseCholesky&&) noexcept;
  SparseCholesky& operator=(SparseCholesky&&) noexcept;
  SparseCholesky(const SparseCholesky&) = delete;
  SparseCholesky& operator=(const SparseCholesky&) = delete;

  /// Orders the rows and columns to reduce fill and computes the symbolic factorization of the
  /// square matrix `pattern` (its values are ignored). Discards any previous factorization.
  /// @throws Error if the matrix is not square.
  void analyze(const SparseMatrix& pattern);

  /// Numeric factorization of A, reusing the analysis (analyzing A first if analyze() was
  /// never called). A must have exactly the analyzed pattern, explicit zeros included.
  /// @throws SolverError "matrix is not positive definite (column k)" (llt) or "matrix is
  ///         singular (zero pivot in column k)" (ldlt), k the original column where the
  ///         factorization broke down, or "matrix is numerically singular (...)" when the
  ///         ratio of the smallest to the largest pivot (CHOLMOD's reciprocal condition
  ///         estimate) is below n·ε (n = rows(), ε = 2.2e-16) or not finite (A has a NaN or
  ///         infinite entry). The ratio bounds 1/cond(A) from above, so a positive definite A is
  ///         rejected only if cond(A) > 1/(n·ε).
  ///         After a SolverError the analysis is kept but there is no factorization: solve()
  ///         throws until a factorize() succeeds.
  /// @throws Error if A's size or pattern differs from the analyzed one.
  void factorize(const SparseMatrix& matrix);

  /// factorize(), reporting a SolverError's condition by returning false instead (for callers
  /// that react, e.g. a Newton solver that shortens its step). Still throws Error on a size or
  /// pattern mismatch, and std::bad_alloc.
  bool try_factorize(const SparseMatrix& matrix);

  /// True after a successful factorize() (until the next analyze() or failed factorize()).
  bool factorized() const noexcept;

  /// x = A⁻¹ b for the last factorized A.
  /// @throws Error if there is no factorization or b does not have rows() entries.
  Eigen::VectorXd solve(const Eigen::VectorXd& b) const;
  /// X = A⁻¹ B for all columns of B (rows()×k) in one pass over the factor.
  /// @throws Error as solve(const Eigen::VectorXd&).
  Eigen::MatrixXd solve(const Eigen::MatrixXd& b) const;
  /// Any other expression (e.g. solve(f - r)), which would otherwise convert to both of the
  /// above: a vector result when it has one column at compile time, else a matrix.
  template <typename Derived>
  auto solve(const Eigen::MatrixBase<Derived>& b) const {
    if constexpr (Derived::ColsAtCompileTime == 1) {
      return solve(Eigen::VectorXd(b));
    } else {
      return solve(Eigen::MatrixXd(b));
    }
  }

  /// The two halves of an llt solve, for the factor itself: with A = PᵀLLᵀP (P the fill-reducing
  /// permutation), solve_lower(B) = L⁻¹PB and solve_upper(B) = PᵀL⁻ᵀB, so
  /// solve_upper(solve_lower(B)) = A⁻¹B and solve_lower(A X) = LᵀP X (used to change to the
  /// coordinates z = LᵀPx in which xᵀAy becomes zᵀw, e.g. for mass-weighted PCA).
  /// @throws Error as solve(), or if kind() is not llt.
  Eigen::MatrixXd solve_lower(const Eigen::MatrixXd& b) const;
  /// See solve_lower().
  Eigen::MatrixXd solve_upper(const Eigen::MatrixXd& b) const;

  /// Size of the analyzed matrix, 0 before analyze().
  Eigen::Index rows() const noexcept;
  Kind kind() const noexcept;

 private:
  struct Data;
  std::unique_ptr<Data> m_data;
};

}  // namespace khz::reduced
