// Modal derivatives (thesis §2.8.3 eq. 2.47 for anchored objects, §2.8.7 eq. 2.60 for free ones).
#include "detail/shared_stage.hpp"
#include "modal_problem.hpp"
#include "unconstrained_derivative_solver.hpp"

#include <khz/reduced/basis/modal_derivatives.hpp>
#include <khz/reduced/errors.hpp>

#include <algorithm>
#include <functional>
#include <optional>
#include <span>
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
// (H is symmetric in all three indices, so g(i, j) = g(j, i)). Shared: each process contracts
// its share of the modes, and the columns are summed over the group (zeros elsewhere).
Eigen::MatrixXd hessian_products(const FemModel& model, const LinearModes& modes,
                                 const std::vector<std::array<int, 2>>& pairs,
                                 const ModalDerivativesOptions& options) {
  const Eigen::Index k = modes.modes.cols();
  detail::SharedStage stage(options.group, options.progress, "Hessian contractions", k);
  Eigen::MatrixXd products =
      Eigen::MatrixXd::Zero(model.num_dofs(), static_cast<Eigen::Index>(pairs.size()));
  stage.run(k, 1, [&](std::int64_t first, std::int64_t last) {
    for (auto j = static_cast<int>(first); j < last; ++j) {
      const SparseMatrix contraction = model.hessian_contraction(modes.modes.col(j));
      for (std::size_t c = 0; c < pairs.size(); ++c) {
        if (pairs[c][1] != j) continue;
        products.col(static_cast<Eigen::Index>(c)).noalias() =
            contraction * modes.modes.col(pairs[c][0]);
      }
    }
  });
  stage.finish();
  if (stage.shared())
    options.group->sum({products.data(), static_cast<std::size_t>(products.size())});
  return products;
}

// Anchored: K Φᵢⱼ = −(H : Ψⱼ)Ψᵢ with the factorization of K, derivatives [first, last)
// (eq. 2.47).
void solve_anchored(const detail::ModalProblem& problem, SymmetricFactorization& stiffness,
                    const Eigen::MatrixXd& products, Eigen::Index first, Eigen::Index last,
                    ModalDerivatives& result) {
  const Eigen::MatrixXd rhs =
      -problem.dofs().restrict_rows(products.middleCols(first, last - first));
  result.vectors.middleCols(first, last - first) = problem.dofs().expand_rows(stiffness.solve(rhs));
}

// Derivatives [first, last) as one block of right-hand sides in lockstep; check_cancel is
// called every MINRES iteration.
void solve_unconstrained(const LinearModes& modes,
                         const detail::UnconstrainedDerivativeSolver& solver,
                         const std::vector<std::array<int, 2>>& pairs,
                         const Eigen::MatrixXd& products, Eigen::Index first, Eigen::Index last,
                         const ModalDerivativesOptions& options,
                         const std::function<void()>& check_cancel, ModalDerivatives& result) {
  // Blocks mix pairs of different i: each column has its own λᵢ, but the operator, the
  // projections and the preconditioner solve still run on the whole block at once.
  const Eigen::Index columns = last - first;
  Eigen::VectorXd lambda(columns);
  for (Eigen::Index c = 0; c < columns; ++c) {
    lambda(c) = modes.eigenvalues(pairs[static_cast<std::size_t>(first + c)][0]);
  }
  detail::MinresReport report;
  result.vectors.middleCols(first, columns) =
      solver.solve(-products.middleCols(first, columns), lambda, options.tolerance,
                   options.max_iterations, check_cancel, report);
  if (!report.converged) {
    throw SolverError("MINRES did not converge for derivatives " + std::to_string(first) + "–" +
                      std::to_string(last - 1) + " in " + std::to_string(options.max_iterations) +
                      " iterations (relative residual " +
                      std::to_string(report.worst_relative_residual) +
                      "); if the object is symmetric, its last modes may have a twin of equal "
                      "eigenvalue past the " +
                      std::to_string(modes.eigenvalues.size()) +
                      " computed: compute more or fewer modes, so that the group is whole");
  }
  result.max_minres_iterations = std::max(result.max_minres_iterations, report.iterations);
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
  const Eigen::MatrixXd products = hessian_products(model, modes, result.pairs, options);
  const auto count = static_cast<Eigen::Index>(result.pairs.size());
  detail::SharedStage stage(options.group, options.progress, "modal derivatives", count);
  // K (anchored) or K − σM with σ < 0 (unconstrained, MINRES's preconditioner), factorized by
  // every process (or by all together, for a collective factorization), and for an
  // unconstrained object the solver's Ritz vectors, which take solves with it; a failure on one
  // process stops all.
  std::unique_ptr<SymmetricFactorization> factor;
  std::optional<detail::UnconstrainedDerivativeSolver> unconstrained;
  stage.agree([&] {
    factor = problem.factorize_shifted(options.factorize);
    if (problem.unconstrained()) unconstrained.emplace(problem, modes, *factor);
  });
  result.vectors = Eigen::MatrixXd::Zero(products.rows(), count);  // zeros: summed when shared
  const auto solve_block = [&](std::int64_t first, std::int64_t last) {
    if (unconstrained) {
      solve_unconstrained(
          modes, *unconstrained, result.pairs, products, first, last, options,
          [&] { stage.poll(); }, result);
    } else {
      solve_anchored(problem, *factor, products, first, last, result);
    }
  };
  // A collective factorization needs every process in every solve: each solves every block,
  // and there is nothing to sum afterwards.
  const bool collective = factor->collective();
  if (collective) {
    stage.run_on_every_process(count, options.block_size, solve_block);
  } else {
    stage.run(count, options.block_size, solve_block);
  }
  stage.finish();
  if (stage.shared() && !collective) {
    options.group->sum({result.vectors.data(), static_cast<std::size_t>(result.vectors.size())});
    result.max_minres_iterations = static_cast<int>(
        detail::largest_on_every_process(*options.group, result.max_minres_iterations));
  }
  return result;
}

}  // namespace khz::reduced
