#pragma once
// The singular value decomposition of a 6×6 matrix by one-sided (Hestenes) Jacobi rotations: the
// equilibrium solve's SVD (thesis §4.10), about three times faster than Eigen's two-sided
// JacobiSVD at this size and as accurate (each singular value to a few ulps of σ₁).

#include <khz/haptic/coupling/equilibrium.hpp>

namespace khz::haptic::detail {

/// A = W Vᵀ with V orthogonal and the columns of W mutually orthogonal: wᵢ = σᵢ uᵢ. Unsorted.
struct ScaledSvd {
  Matrix6d w;
  Matrix6d v;
  Vector6d sigma;  ///< ‖wᵢ‖.
};

/// Rotates pairs of columns of A (and of V = I) until every pair is orthogonal to within
/// 1e-15 relative, at most 30 sweeps. Allocates nothing; finite A gives a finite result.
ScaledSvd one_sided_jacobi(const Matrix6d& a) noexcept;

}  // namespace khz::haptic::detail
