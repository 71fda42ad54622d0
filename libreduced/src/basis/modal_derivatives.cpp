// Modal derivatives (thesis §2.8.3 eq. 2.47 for anchored objects, §2.8.7 eq. 2.60 for free ones).
#include <khz/reduced/stage_progress.hpp>
#include "block_minres.hpp"
#include "modal_problem.hpp"

#include <khz/reduced/basis/modal_derivatives.hpp>
#include <khz/reduced/errors.hpp>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace khz::reduced {

namespace {

void check_inputs(const FemModel& model, const LinearModes& modes,
                  const ModalDerivativesOptions& options) {
  if (options.block_size < 1) throw Error("block_size must be at least 1");
  if (!(options.tolerance > 0.0 && options.tolerance < 1.0)) {
    throw Error("tolerance must lie in (0, 1)");
  }
  if (options.max_iterations < 1) throw Error("max_iterations must be at least 1");
  const Eigen::Index k = modes.modes.cols();
  if (k < 1 || modes.modes.rows() != model.num_dofs() || modes.eigenvalues.size() != k) {
    throw Error("the linear modes (" + std::to_string(modes.modes.rows()) + "×" +
                std::to_string(k) + ", " + std::to_string(modes.eigenvalues.size()) +
                " eigenvalues) do not belong to this model (" + std::to_string(model.num_dofs()) +
                " dofs)");
  }
  if (!(modes.eigenvalues.minCoeff() > 0.0)) {
    throw Error(
        "the linear modes must have positive eigenvalues (rigid modes belong in "
        "LinearModes::rigid_modes)");
  }
}

// g(i, j) = (H : Ψⱼ) Ψᵢ for every wanted pair, full dofs, one Hessian contraction per mode j
// (H is symmetric in all three indices, so g(i, j) = g(j, i)).
Eigen::MatrixXd hessian_products(const FemModel& model, const LinearModes& modes,
                                 const std::vector<std::array<int, 2>>& pairs,
                                 const ProgressCallback& callback) {
  const Eigen::Index k = modes.modes.cols();
  StageProgress progress(callback, "Hessian contractions", k);
  Eigen::MatrixXd products(model.num_dofs(), static_cast<Eigen::Index>(pairs.size()));
  for (int j = 0; j < k; ++j) {
    const SparseMatrix contraction = model.hessian_contraction(modes.modes.col(j));
    for (std::size_t c = 0; c < pairs.size(); ++c) {
      if (pairs[c][1] != j) continue;
      products.col(static_cast<Eigen::Index>(c)).noalias() =
          contraction * modes.modes.col(pairs[c][0]);
    }
    progress.advance();
  }
  return products;
}

// Anchored: K Φᵢⱼ = −(H : Ψⱼ)Ψᵢ, one factorization, right-hand sides in blocks (eq. 2.47).
void solve_anchored(const detail::ModalProblem& problem, const Eigen::MatrixXd& products,
                    const ModalDerivativesOptions& options, ModalDerivatives& result) {
  const Eigen::Index count = products.cols();
  StageProgress progress(options.progress, "modal derivatives", count);
  const SparseCholesky stiffness = problem.factorize_shifted();  // σ = 0: K itself
  const Eigen::MatrixXd rhs = -problem.dofs().restrict_rows(products);
  result.vectors.resize(products.rows(), count);
  for (Eigen::Index first = 0; first < count; first += options.block_size) {
    const Eigen::Index columns = std::min<Eigen::Index>(options.block_size, count - first);
    result.vectors.middleCols(first, columns) = problem.dofs().expand_rows(
        stiffness.solve(Eigen::MatrixXd(rhs.middleCols(first, columns))));
    progress.advance(columns);
  }
}

// Unconstrained: (K − λᵢM) Φᵢⱼ = (MΨᵢΨᵢᵀ − I)(H : Ψⱼ)Ψᵢ (eq. 2.60). K − λᵢM is singular along
// Ψᵢ; the right-hand side lies in its range, and the regularized operator K − λᵢM + ΨᵢΨᵢᵀ
// (nonsingular, symmetric, indefinite) has the same solution, which MINRES finds. Modes whose
// eigenvalue equals λᵢ to 1e-6 (symmetric shapes) make the derivative ambiguous along them, so
// the whole cluster is treated like Ψᵢ: projected out of the right-hand side, added to the
// regularizer, and removed from the solution.
void solve_unconstrained(const detail::ModalProblem& problem, const LinearModes& modes,
                         const std::vector<std::array<int, 2>>& pairs,
                         const Eigen::MatrixXd& products, const ModalDerivativesOptions& options,
                         ModalDerivatives& result) {
  const Eigen::Index count = products.cols();
  StageProgress progress(options.progress, "modal derivatives", count);
  const SparseCholesky preconditioner = problem.factorize_shifted();  // K − σM, σ < 0
  const SparseMatrix& mass = problem.mass();
  const Eigen::Index k = modes.modes.cols();
  // Per mode i: its cluster Ψ_C (modes with λ equal to λᵢ within 1e-6) and MΨ_C.
  std::vector<Eigen::MatrixXd> psi(static_cast<std::size_t>(k));
  std::vector<Eigen::MatrixXd> mass_psi(static_cast<std::size_t>(k));
  for (Eigen::Index i = 0; i < k; ++i) {
    std::vector<Eigen::Index> cluster;
    for (Eigen::Index m = 0; m < k; ++m) {
      if (std::abs(modes.eigenvalues(m) - modes.eigenvalues(i)) <= 1e-6 * modes.eigenvalues(i)) {
        cluster.push_back(m);
      }
    }
    psi[static_cast<std::size_t>(i)] = modes.modes(Eigen::all, cluster);
    mass_psi[static_cast<std::size_t>(i)] = mass * psi[static_cast<std::size_t>(i)];
  }
  result.vectors.resize(products.rows(), count);
  // Blocks mix pairs of different i: each column has its own operator K − λᵢM + Ψ_CΨ_Cᵀ, but
  // K·X, M·X and the preconditioner solve still run on the whole block at once.
  for (Eigen::Index first = 0; first < count; first += options.block_size) {
    const Eigen::Index columns = std::min<Eigen::Index>(options.block_size, count - first);
    const auto mode_of = [&](Eigen::Index c) {
      return static_cast<std::size_t>(pairs[static_cast<std::size_t>(first + c)][0]);
    };
    Eigen::VectorXd lambda(columns);
    Eigen::MatrixXd rhs = -products.middleCols(first, columns);
    for (Eigen::Index c = 0; c < columns; ++c) {
      const std::size_t i = mode_of(c);
      lambda(c) = modes.eigenvalues(static_cast<Eigen::Index>(i));
      rhs.col(c) -= mass_psi[i] * (psi[i].transpose() * rhs.col(c));  // (MΨΨᵀ − I) g
    }
    const auto apply = [&](const Eigen::MatrixXd& x, Eigen::MatrixXd& y) {
      y.noalias() = problem.stiffness() * x;
      y.noalias() -= (mass * x) * lambda.asDiagonal();
      for (Eigen::Index c = 0; c < columns; ++c) {
        y.col(c).noalias() += psi[mode_of(c)] * (psi[mode_of(c)].transpose() * x.col(c));
      }
    };
    const auto precondition = [&](const Eigen::MatrixXd& x, Eigen::MatrixXd& y) {
      y = preconditioner.solve(x);
    };
    const auto check_cancel = [&] { progress.advance(0); };
    Eigen::MatrixXd phi;
    const detail::MinresReport report = detail::block_minres(
        apply, precondition, rhs, options.tolerance, options.max_iterations, check_cancel, phi);
    if (!report.converged) {
      throw SolverError("MINRES did not converge for derivatives " + std::to_string(first) + "–" +
                        std::to_string(first + columns - 1) + " in " +
                        std::to_string(options.max_iterations) + " iterations (relative residual " +
                        std::to_string(report.worst_relative_residual) + ")");
    }
    for (Eigen::Index c = 0; c < columns; ++c) {
      const std::size_t i = mode_of(c);
      phi.col(c) -= psi[i] * (mass_psi[i].transpose() * phi.col(c));  // Ψᵢᵀ M Φᵢⱼ = 0
    }
    result.vectors.middleCols(first, columns) = phi;
    result.max_minres_iterations = std::max(result.max_minres_iterations, report.iterations);
    progress.advance(columns);
  }
}

}  // namespace

ModalDerivatives compute_modal_derivatives(const FemModel& model, const LinearModes& modes,
                                           const ModalDerivativesOptions& options) {
  check_inputs(model, modes, options);
  const detail::ModalProblem problem(model, modes.fixed_vertices, modes.mass);
  const auto k = static_cast<int>(modes.modes.cols());
  ModalDerivatives result;
  for (int i = 0; i < k; ++i) {
    for (int j = problem.unconstrained() ? 0 : i; j < k; ++j) result.pairs.push_back({i, j});
  }
  const Eigen::MatrixXd products = hessian_products(model, modes, result.pairs, options.progress);
  if (problem.unconstrained()) {
    solve_unconstrained(problem, modes, result.pairs, products, options, result);
  } else {
    solve_anchored(problem, products, options, result);
  }
  return result;
}

}  // namespace khz::reduced
