#include "coupling/one_sided_jacobi.hpp"

#include <cmath>

namespace khz::haptic::detail {
namespace {

// The 15 column pairs in 5 rounds of 3 disjoint pairs (a round-robin tournament), so that
// consecutive rotations are independent and overlap in the pipeline.
constexpr int pairs[15][2] = {{0, 1}, {2, 3}, {4, 5}, {0, 2}, {1, 4}, {3, 5}, {0, 3}, {1, 5},
                              {2, 4}, {0, 4}, {1, 3}, {2, 5}, {0, 5}, {1, 2}, {3, 4}};

}  // namespace

ScaledSvd one_sided_jacobi(const Matrix6d& a) noexcept {
  ScaledSvd svd{a, Matrix6d::Identity(), Vector6d::Zero()};
  Matrix6d& w = svd.w;
  Matrix6d& v = svd.v;
  for (int sweep = 0; sweep < 30; ++sweep) {
    bool rotated = false;
    for (const auto& [p, q] : pairs) {
      const double alpha = w.col(p).squaredNorm();
      const double beta = w.col(q).squaredNorm();
      const double gamma = w.col(p).dot(w.col(q));
      if (std::abs(gamma) <= 1e-15 * std::sqrt(alpha * beta)) continue;
      rotated = true;
      // The rotation diagonalizing [α γ; γ β]: t = tan φ, the smaller root of t² + 2ζt − 1 = 0.
      const double zeta = (beta - alpha) / (2.0 * gamma);
      const double t = std::copysign(1.0, zeta) / (std::abs(zeta) + std::sqrt(1.0 + zeta * zeta));
      const double c = 1.0 / std::sqrt(1.0 + t * t);
      const double s = c * t;
      const Vector6d wp = w.col(p);
      const Vector6d vp = v.col(p);
      w.col(p) = c * wp - s * w.col(q);
      w.col(q) = s * wp + c * w.col(q);
      v.col(p) = c * vp - s * v.col(q);
      v.col(q) = s * vp + c * v.col(q);
    }
    if (!rotated) break;
  }
  svd.sigma = w.colwise().norm().transpose();
  return svd;
}

}  // namespace khz::haptic::detail
