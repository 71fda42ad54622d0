#include <khz/reduced/stage_progress.hpp>
#include "../detail/backtracking_line_search.hpp"

#include <khz/reduced/errors.hpp>
#include <khz/reduced/solvers/fixed_dofs.hpp>
#include <khz/reduced/solvers/sparse_cholesky.hpp>
#include <khz/reduced/solvers/static_solver.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <string>

namespace khz::reduced {
namespace {

/// The out-of-balance force R(u) − f on the free dofs.
class Residual {
 public:
  Residual(const FemModel& model, const FixedDofs& fixed) : m_model(model), m_fixed(fixed) {}

  Eigen::VectorXd operator()(const Eigen::VectorXd& u_full, const Eigen::VectorXd& f_free) {
    m_model.internal_forces(u_full, m_forces);
    return m_fixed.restrict_vector(m_forces) - f_free;
  }

 private:
  const FemModel& m_model;
  const FixedDofs& m_fixed;
  Eigen::VectorXd m_forces;
};

std::string describe(int load_step, int load_steps, int iteration, double residual) {
  char text[128];
  std::snprintf(text, sizeof text, "load step %d/%d, Newton iteration %d (residual %.3g N)",
                load_step, load_steps, iteration, residual);
  return text;
}

void validate(const StaticSolveOptions& options) {
  if (options.load_steps < 1 || options.max_iterations < 1 || !(options.tolerance > 0)) {
    throw Error(
        "solve_static: load_steps and max_iterations must be at least 1 and tolerance "
        "positive");
  }
}

}  // namespace

StaticSolution solve_static(const FemModel& model, std::span<const int> fixed_vertices,
                            const Eigen::VectorXd& external_force,
                            const StaticSolveOptions& options) {
  validate(options);
  if (external_force.size() != model.num_dofs() || !external_force.allFinite()) {
    throw Error("solve_static: the force must have " + std::to_string(model.num_dofs()) +
                " finite entries");
  }
  const FixedDofs fixed(model.mesh().num_vertices(), fixed_vertices);
  SparseMatrix stiffness_full = model.stiffness_pattern();
  SparseMatrix stiffness = fixed.restrict_matrix(stiffness_full);
  SparseCholesky cholesky(SparseCholesky::Kind::llt);
  std::optional<SparseCholesky> ldlt;  // only made when K(u) turns indefinite
  cholesky.analyze(stiffness);
  Residual residual_of(model, fixed);

  const Eigen::VectorXd f_total = fixed.restrict_vector(external_force);
  const double tolerance = options.tolerance * std::max(f_total.norm(), 1e-12);
  StaticSolution solution;
  Eigen::VectorXd u = Eigen::VectorXd::Zero(fixed.num_free_dofs());
  Eigen::VectorXd u_full = Eigen::VectorXd::Zero(model.num_dofs());
  Eigen::VectorXd forces_full;

  // Thesis §2.1.10: Newton–Raphson on R(u) = f, here with the load applied in increments.
  StageProgress progress(options.progress, "static solve", options.load_steps);
  for (int step = 1; step <= options.load_steps; ++step) {
    const Eigen::VectorXd f = f_total * (static_cast<double>(step) / options.load_steps);
    for (int iteration = 0;; ++iteration) {
      model.forces_and_stiffness(u_full, forces_full, stiffness_full);
      const Eigen::VectorXd residual = fixed.restrict_vector(forces_full) - f;
      solution.residual_norm = residual.norm();
      if (solution.residual_norm <= tolerance) break;
      if (iteration == options.max_iterations || !std::isfinite(solution.residual_norm)) {
        throw SolverError("solve_static: no convergence at " +
                          describe(step, options.load_steps, iteration, solution.residual_norm) +
                          "; try more load_steps");
      }
      fixed.restrict_matrix_values(stiffness_full, stiffness);
      const SparseCholesky* factor = &cholesky;
      if (!cholesky.try_factorize(stiffness)) {
        if (!ldlt) {
          ldlt.emplace(SparseCholesky::Kind::ldlt);
          ldlt->analyze(stiffness);
        }
        if (!ldlt->try_factorize(stiffness)) {
          throw SolverError("solve_static: singular stiffness at " +
                            describe(step, options.load_steps, iteration, solution.residual_norm) +
                            " (are the rigid motions fixed?)");
        }
        factor = &*ldlt;
      }
      const Eigen::VectorXd direction = -factor->solve(residual);

      Eigen::VectorXd trial = u + direction;
      if (options.line_search) {
        const double energy = model.strain_energy(u_full) - f.dot(u);
        const auto accepted = detail::backtracking_line_search(
            energy, residual.dot(direction), solution.residual_norm, [&](double length) {
              trial = u + length * direction;
              fixed.expand_vector(trial, u_full);
              return detail::TrialMerits{residual_of(u_full, f).norm(),
                                         model.strain_energy(u_full) - f.dot(trial)};
            });
        if (!accepted) {
          throw SolverError(
              "solve_static: line search found no decrease at " +
              describe(step, options.load_steps, iteration, solution.residual_norm) +
              "; the tolerance may be below round-off, or the stiffness singular (are the rigid "
              "motions fixed?)");
        }
      }
      u = trial;
      fixed.expand_vector(u, u_full);
      ++solution.iterations;
      progress.advance(0);  // a chance to cancel
    }
    progress.advance();
  }
  solution.displacement = u_full;
  return solution;
}

}  // namespace khz::reduced
