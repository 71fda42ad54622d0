#include <khz/reduced/errors.hpp>
#include <khz/reduced/subspace/reduced_static.hpp>

#include <khz/reduced/stage_progress.hpp>
#include "detail/backtracking_line_search.hpp"
#include "subspace/dense_symmetric_solve.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

namespace khz::reduced {

void ReducedStaticOptions::validate() const {
  if (load_steps < 1 || max_iterations < 1 || !(tolerance > 0) || !std::isfinite(tolerance)) {
    throw Error(
        "solve_reduced_static: load_steps and max_iterations must be at least 1 and tolerance "
        "positive");
  }
}

namespace {

std::string describe(int load_step, int load_steps, int iteration, double residual) {
  char text[128];
  std::snprintf(text, sizeof text, "load step %d/%d, Newton iteration %d (residual %.3g)",
                load_step, load_steps, iteration, residual);
  return text;
}

}  // namespace

ReducedStaticSolution solve_reduced_static(ReducedForceModel& forces,
                                           const Eigen::VectorXd& external_force,
                                           const ReducedStaticOptions& options) {
  options.validate();
  const Eigen::Index r = forces.dimension();
  if (r < 1) throw Error("solve_reduced_static: the force model has no reduced coordinates");
  if (external_force.size() != r || !external_force.allFinite()) {
    throw Error("solve_reduced_static: the force must have " + std::to_string(r) +
                " finite entries");
  }
  const Eigen::VectorXd& guess = options.initial_guess;
  if (guess.size() != 0 && (guess.size() != r || !guess.allFinite())) {
    throw Error("solve_reduced_static: the initial guess must have " + std::to_string(r) +
                " finite entries (or none)");
  }

  ReducedStaticSolution solution;
  Eigen::VectorXd q = guess.size() == 0 ? Eigen::VectorXd::Zero(r) : guess;
  Eigen::VectorXd internal(r);
  Eigen::MatrixXd stiffness(r, r);
  forces.evaluate_forces(q, internal);
  if (!internal.allFinite()) {
    throw SolverError("solve_reduced_static: non-finite forces at the initial guess");
  }
  const Eigen::VectorXd start_force = internal;  // R̃(q₀), carried by the guess
  const double tolerance =
      options.tolerance * std::max({external_force.norm(), start_force.norm(), 1e-12});
  detail::DenseSymmetricSolver solver(r);
  Eigen::VectorXd residual(r), direction(r), trial(r);

  // Thesis §2.1.10: Newton–Raphson on R̃(q) = f̃, here with the load applied in increments.
  StageProgress progress(options.progress, "reduced static solve", options.load_steps);
  for (int step = 1; step <= options.load_steps; ++step) {
    const double fraction = static_cast<double>(step) / options.load_steps;
    const Eigen::VectorXd f = start_force + fraction * (external_force - start_force);
    for (int iteration = 0;; ++iteration) {
      forces.evaluate(q, internal, stiffness);
      residual = internal - f;
      solution.residual_norm = residual.norm();
      if (solution.residual_norm <= tolerance) break;
      if (iteration == options.max_iterations || !std::isfinite(solution.residual_norm) ||
          !stiffness.allFinite()) {
        throw SolverError("solve_reduced_static: no convergence at " +
                          describe(step, options.load_steps, iteration, solution.residual_norm) +
                          "; try more load_steps, or the load exceeds what the model carries");
      }
      direction = -residual;
      if (solver.solve_in_place(stiffness, direction) == detail::DenseSolve::failed) {
        throw SolverError("solve_reduced_static: the Newton system could not be solved at " +
                          describe(step, options.load_steps, iteration, solution.residual_norm));
      }

      if (options.line_search) {
        const auto accepted = detail::backtracking_line_search(
            forces.energy(q) - f.dot(q), residual.dot(direction), solution.residual_norm,
            [&](double length) {
              trial = q + length * direction;
              forces.evaluate_forces(trial, internal);
              return detail::TrialMerits{(internal - f).norm(),
                                         forces.energy(trial) - f.dot(trial)};
            });
        if (!accepted) {
          throw SolverError(
              "solve_reduced_static: line search found no decrease at " +
              describe(step, options.load_steps, iteration, solution.residual_norm) +
              "; the load may exceed what the model carries, or the tolerance be below round-off");
        }
      } else {
        trial = q + direction;
      }
      q = trial;
      ++solution.iterations;
      progress.advance(0);  // a chance to cancel
    }
    progress.advance();
  }
  solution.coordinates = q;
  return solution;
}

}  // namespace khz::reduced
