#pragma once
// Preconditioned MINRES (Paige & Saunders 1975) for several right-hand sides in lockstep: each
// column runs its own recurrence, but the operator and the preconditioner are applied to all
// active columns at once, so sparse products and triangular solves work on blocks.

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <limits>

namespace khz::reduced::detail {

/// Outcome of block_minres().
struct MinresReport {
  bool converged = false;
  int iterations = 0;                  ///< Iterations of the slowest column.
  double worst_relative_residual = 0;  ///< max over columns of the estimate ‖r‖_{P} / ‖b‖_{P}.
};

/// Solves A X = B for symmetric (possibly indefinite) A with a symmetric positive definite
/// preconditioner P ≈ A⁻¹ in the sense of its norm: apply(X, Y) sets Y = A X and
/// precondition(X, Y) sets Y = P X, both for n × c blocks. A column stops when its residual
/// estimate, measured in the P-norm, falls below tolerance times that of its right-hand side.
/// check() is called once per iteration (e.g. to honour cancellation by throwing).
template <typename Apply, typename Precondition, typename Check>
MinresReport block_minres(const Apply& apply, const Precondition& precondition,
                          const Eigen::MatrixXd& b, double tolerance, int max_iterations,
                          const Check& check, Eigen::MatrixXd& x) {
  using Eigen::ArrayXd;
  using Eigen::MatrixXd;
  const Eigen::Index n = b.rows();
  const Eigen::Index c = b.cols();
  x = MatrixXd::Zero(n, c);
  MatrixXd r1 = b;
  MatrixXd r2 = b;
  MatrixXd y;
  precondition(r1, y);
  const ArrayXd beta1 = (r1.cwiseProduct(y)).colwise().sum().transpose().array().sqrt();
  ArrayXd beta = beta1;
  ArrayXd old_beta = ArrayXd::Zero(c);
  ArrayXd alpha = ArrayXd::Zero(c);
  ArrayXd dbar = ArrayXd::Zero(c);
  ArrayXd epsilon = ArrayXd::Zero(c);
  ArrayXd phibar = beta1;
  ArrayXd cs = ArrayXd::Constant(c, -1.0);
  ArrayXd sn = ArrayXd::Zero(c);
  MatrixXd w = MatrixXd::Zero(n, c);
  MatrixXd w1 = MatrixXd::Zero(n, c);
  MatrixXd w2 = MatrixXd::Zero(n, c);
  MatrixXd v(n, c);
  Eigen::Array<bool, Eigen::Dynamic, 1> active = beta1 > 0.0;

  MinresReport report;
  for (int iteration = 1; iteration <= max_iterations && active.any(); ++iteration) {
    check();
    report.iterations = iteration;
    for (Eigen::Index j = 0; j < c; ++j) {
      v.col(j) = active(j) ? (y.col(j) / beta(j)).eval() : Eigen::VectorXd::Zero(n);
    }
    apply(v, y);
    for (Eigen::Index j = 0; j < c; ++j) {
      if (!active(j)) continue;
      if (iteration >= 2) y.col(j) -= (beta(j) / old_beta(j)) * r1.col(j);
      alpha(j) = v.col(j).dot(y.col(j));
      y.col(j) -= (alpha(j) / beta(j)) * r2.col(j);
      r1.col(j) = r2.col(j);
      r2.col(j) = y.col(j);
    }
    precondition(r2, y);
    for (Eigen::Index j = 0; j < c; ++j) {
      if (!active(j)) continue;
      old_beta(j) = beta(j);
      beta(j) = std::sqrt(std::max(r2.col(j).dot(y.col(j)), 0.0));
      // Apply the previous rotation, then compute the next one.
      const double old_epsilon = epsilon(j);
      const double delta = cs(j) * dbar(j) + sn(j) * alpha(j);
      const double gbar = sn(j) * dbar(j) - cs(j) * alpha(j);
      epsilon(j) = sn(j) * beta(j);
      dbar(j) = -cs(j) * beta(j);
      const double gamma = std::max(std::hypot(gbar, beta(j)), std::numeric_limits<double>::min());
      cs(j) = gbar / gamma;
      sn(j) = beta(j) / gamma;
      const double phi = cs(j) * phibar(j);
      phibar(j) = sn(j) * phibar(j);
      w1.col(j) = w2.col(j);
      w2.col(j) = w.col(j);
      w.col(j) = (v.col(j) - old_epsilon * w1.col(j) - delta * w2.col(j)) / gamma;
      x.col(j) += phi * w.col(j);
      if (phibar(j) <= tolerance * beta1(j) || beta(j) == 0.0) active(j) = false;
    }
  }
  report.converged = !active.any();
  for (Eigen::Index j = 0; j < c; ++j) {
    if (beta1(j) > 0.0) {
      report.worst_relative_residual =
          std::max(report.worst_relative_residual, phibar(j) / beta1(j));
    }
  }
  return report;
}

}  // namespace khz::reduced::detail
