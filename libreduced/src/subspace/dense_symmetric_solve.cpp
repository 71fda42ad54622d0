#include "subspace/dense_symmetric_solve.hpp"

#include "subspace/simd_lanes.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>

namespace khz::reduced::detail {
namespace {

/// Eigenvalues with |λ| at or below this fraction of max|λ| count as zero in the pseudo-inverse.
constexpr double zero_eigenvalue = 1e-12;

}  // namespace

DenseSymmetricSolver::DenseSymmetricSolver(Eigen::Index size)
    : m_factor(Eigen::MatrixXd::Zero(size + kLanes, size)),
      m_inverse_pivots(size),
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
  if (factor_ldlt(matrix, rhs_and_solution)) {
    back_substitute(rhs_and_solution);
    // A NaN pivot passes the positivity test, so non-finite input surfaces here.
    return rhs_and_solution.allFinite() ? DenseSolve::cholesky : DenseSolve::failed;
  }
  return solve_by_eigendecomposition(matrix, rhs_and_solution) ? DenseSolve::eigen_fallback
                                                               : DenseSolve::failed;
}

bool DenseSymmetricSolver::factor_ldlt(const Eigen::MatrixXd& matrix,
                                       const Eigen::VectorXd& rhs) noexcept {
  const auto n = static_cast<int>(matrix.rows());
  const auto stride = static_cast<int>(m_factor.rows());
  double* const c = m_factor.data();
  const double* const a = matrix.data();
  alignas(64) double lanes[kLanes];
  // Left-looking LDLᵀ of [A b; bᵀ ·] with C = LD stored by columns: column j is
  // Â(j:n+1, j) − Σ_k C(j:n+1, k) L(j, k), accumulated in eight-row chunks of lanes and stored
  // whole; its pivot is d_j. Row n of C is yᵀ with L y = b, so the forward substitution rides
  // along at no extra latency. Row j of L (C's column scaled by 1/d_j) goes into the upper
  // triangle, where it is read contiguously here and by columns in the back substitution. At
  // r ≤ 60 all of this is bound by latency, not arithmetic: LDLᵀ keeps the square root off the
  // chain of pivots, and the padding rows let every store be a full, unmasked one, which later
  // loads can forward from.
  for (int j = 0; j < n; ++j) {
    double* const column = c + j * stride;  // below the diagonal C(:, j), above it L(j, :)
    double inverse_pivot = 0.0;
    for (int chunk = j; chunk <= n; chunk += kLanes) {
      const int count = std::min(kLanes, n + 1 - chunk);  // rows of the chunk, the last one b
      Lanes even = load_first(a + j * n + chunk, std::min(count, n - chunk));
      if (chunk + count > n) even = with_lane(even, n - chunk, rhs[j]);
      Lanes odd = zero_lanes();  // two accumulators halve the dependency chain
      int k = 0;
      for (; k + 1 < j; k += 2) {
        even = fma(broadcast(-column[k]), load(c + k * stride + chunk), even);
        odd = fma(broadcast(-column[k + 1]), load(c + (k + 1) * stride + chunk), odd);
      }
      if (k < j) even = fma(broadcast(-column[k]), load(c + k * stride + chunk), even);
      const Lanes sum = even + odd;
      if (chunk == j) {
        const double pivot = first_lane(sum);
        if (!(pivot > 0.0)) return false;  // also false for NaN
        inverse_pivot = 1.0 / pivot;
        m_inverse_pivots[j] = inverse_pivot;
      }
      store(column + chunk, sum);  // rows past n are padding and stay zero
      store(lanes, sum * broadcast(inverse_pivot));
      for (int i = 0; i < std::min(count, n - chunk); ++i) c[(chunk + i) * stride + j] = lanes[i];
    }
  }
  return true;
}

void DenseSymmetricSolver::back_substitute(Eigen::VectorXd& x) const noexcept {
  const auto n = static_cast<int>(x.size());
  const auto stride = static_cast<int>(m_factor.rows());
  const double* const c = m_factor.data();
  double* const b = x.data();
  // D⁻¹ y with y = D z the row C(n, :).
  for (int k = 0; k < n; ++k) b[k] = c[k * stride + n] * m_inverse_pivots[k];
  // Lᵀ x = D⁻¹ y by subtracting columns of Lᵀ (the upper triangle): scalar loads and stores of x
  // forward cheaply, where dot products would wait on them.
  for (int k = n - 1; k > 0; --k) {
    const double value = b[k];
    const double* const column = c + k * stride;
    for (int i = 0; i < k; ++i) b[i] -= column[i] * value;
  }
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
