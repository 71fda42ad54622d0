#pragma once
// Preconditioned MINRES (Paige & Saunders 1975) for several right-hand sides in lockstep: each
// column runs its own recurrence, but the operator and the preconditioner are applied to all
// active columns at once, so sparse products and triangular solves work on blocks.

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>
#include <vector>

namespace khz::reduced::detail {

/// Outcome of block_minres().
struct MinresReport {
  bool converged = false;
  int iterations = 0;                  ///< Iterations of the slowest column.
  double worst_relative_residual = 0;  ///< max over columns of the estimate ‖r‖_{P} / ‖b‖_{P}.
};

/// Solves A X = B for symmetric (possibly indefinite) A with a symmetric positive definite
/// preconditioner P ≈ A⁻¹ in the sense of its norm. apply(X, columns, Y) sets Y = A X for an
/// n × m block whose column k belongs to right-hand side columns[k] (A may differ per
/// right-hand side); precondition(X, Y) sets Y = P X. Only the columns still iterating are
/// passed, so a block costs the sum of its columns' iterations, not the slowest column's times
/// the block's width. A column stops when its residual estimate, measured in the P-norm, falls
/// below tolerance times that of its right-hand side. check() is called once per iteration
/// (e.g. to honour cancellation by throwing).
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
  MatrixXd z;  // P r2 of every column
  precondition(r1, z);
  const ArrayXd beta1 = (r1.cwiseProduct(z)).colwise().sum().transpose().array().sqrt();
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
  Eigen::Array<bool, Eigen::Dynamic, 1> active = beta1 > 0.0;
  std::vector<Eigen::Index> live;  // the active columns, in order
  MatrixXd v;                      // their Lanczos vectors
  MatrixXd live_block;             // A v, then r2 of the live columns
  MatrixXd live_z;                 // P r2 of the live columns

  MinresReport report;
  for (int iteration = 1; iteration <= max_iterations && active.any(); ++iteration) {
    check();
    report.iterations = iteration;
    live.clear();
    for (Eigen::Index j = 0; j < c; ++j) {
      if (active(j)) live.push_back(j);
    }
    const auto m = static_cast<Eigen::Index>(live.size());
    v.resize(n, m);
    for (Eigen::Index k = 0; k < m; ++k) v.col(k) = z.col(live[k]) / beta(live[k]);
    apply(v, std::as_const(live), live_block);
    for (Eigen::Index k = 0; k < m; ++k) {
      const Eigen::Index j = live[k];
      auto av = live_block.col(k);
      if (iteration >= 2) av -= (beta(j) / old_beta(j)) * r1.col(j);
      alpha(j) = v.col(k).dot(av);
      av -= (alpha(j) / beta(j)) * r2.col(j);
      r1.col(j) = r2.col(j);
      r2.col(j) = av;
    }
    precondition(live_block, live_z);
    for (Eigen::Index k = 0; k < m; ++k) {
      const Eigen::Index j = live[k];
      z.col(j) = live_z.col(k);
      old_beta(j) = beta(j);
      beta(j) = std::sqrt(std::max(r2.col(j).dot(z.col(j)), 0.0));
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
      w.col(j) = (v.col(k) - old_epsilon * w1.col(j) - delta * w2.col(j)) / gamma;
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
