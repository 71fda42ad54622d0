#include "subspace/dense_symmetric_solve.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>

namespace khz::reduced::detail {
namespace {

/// Eigenvalues with |λ| at or below this fraction of max|λ| count as zero in the pseudo-inverse.
constexpr double zero_eigenvalue = 1e-12;

}  // namespace

DenseSymmetricSolver::DenseSymmetricSolver(Eigen::Index size)
    : m_cholesky(size),
      m_packed(size, size),
      m_householder(size - 1),
      m_diagonal(size),
      m_subdiagonal(size - 1),
      m_eigen_coordinates(size),
      m_tridiagonal_eigen(size) {}

DenseSolve DenseSymmetricSolver::solve_in_place(const Eigen::MatrixXd& matrix,
                                                Eigen::VectorXd& rhs_and_solution) noexcept {
  assert(matrix.rows() == m_packed.rows() && matrix.cols() == m_packed.rows() &&
         rhs_and_solution.size() == m_packed.rows());
  if (m_cholesky.compute(matrix).info() == Eigen::Success) {
    m_cholesky.solveInPlace(rhs_and_solution);
    // A NaN pivot passes the positivity test, so non-finite input surfaces here.
    return rhs_and_solution.allFinite() ? DenseSolve::cholesky : DenseSolve::failed;
  }
  return solve_by_eigendecomposition(matrix, rhs_and_solution) ? DenseSolve::eigen_fallback
                                                               : DenseSolve::failed;
}

bool DenseSymmetricSolver::solve_by_eigendecomposition(const Eigen::MatrixXd& matrix,
                                                       Eigen::VectorXd& x) noexcept {
  const Eigen::Index n = matrix.rows();
  // Scaled to entries in [−1, 1] against overflow, as SelfAdjointEigenSolver does.
  m_packed = matrix;
  const double scale = m_packed.cwiseAbs().maxCoeff();
  if (!std::isfinite(scale) || !x.allFinite()) return false;
  if (scale == 0.0) {  // A = 0: its pseudo-inverse is 0
    x.setZero();
    return true;
  }
  m_packed /= scale;
  // A = Q T Qᵀ with Q = H_0 H_1 … H_{n−2} (reflectors stored below the subdiagonal).
  Eigen::internal::tridiagonalization_inplace(m_packed, m_householder);
  m_diagonal = m_packed.diagonal();
  m_subdiagonal = m_packed.diagonal<-1>();
  m_tridiagonal_eigen.computeFromTridiagonal(m_diagonal, m_subdiagonal, Eigen::ComputeEigenvectors);
  if (m_tridiagonal_eigen.info() != Eigen::Success) return false;

  const Eigen::VectorXd& eigenvalues = m_tridiagonal_eigen.eigenvalues();  // ascending
  const Eigen::MatrixXd& eigenvectors = m_tridiagonal_eigen.eigenvectors();
  const double threshold =
      zero_eigenvalue * std::max(std::abs(eigenvalues(0)), std::abs(eigenvalues(n - 1)));
  for (Eigen::Index k = 0; k + 1 < n; ++k) apply_reflector(k, x);  // Qᵀ b
  m_eigen_coordinates.noalias() = eigenvectors.transpose() * x;
  for (Eigen::Index i = 0; i < n; ++i) {
    const double lambda = eigenvalues(i);
    m_eigen_coordinates(i) = std::abs(lambda) > threshold ? m_eigen_coordinates(i) / lambda : 0.0;
  }
  x.noalias() = eigenvectors * m_eigen_coordinates;
  for (Eigen::Index k = n - 2; k >= 0; --k) apply_reflector(k, x);  // Q y
  x /= scale;
  return x.allFinite();
}

void DenseSymmetricSolver::apply_reflector(Eigen::Index k, Eigen::VectorXd& x) const noexcept {
  // v_k = [0, …, 0, 1, m_packed(k+2 : n−1, k)] with its 1 at row k + 1.
  const Eigen::Index tail = m_packed.rows() - k - 2;
  const auto essential = m_packed.col(k).tail(tail);
  const double w = m_householder(k) * (x(k + 1) + essential.dot(x.tail(tail)));
  x(k + 1) -= w;
  x.tail(tail) -= w * essential;
}

}  // namespace khz::reduced::detail
