#pragma once
// Static equilibrium R̃(q) = f̃ of a reduced model (thesis §2.1.10 applied to eq. 2.21 at rest).

#include <khz/reduced/export.hpp>
#include <khz/reduced/progress.hpp>
#include <khz/reduced/subspace/reduced_forces.hpp>

#include <Eigen/Core>

namespace khz::reduced {

/// Options of solve_reduced_static().
struct KHZ_REDUCED_API ReducedStaticOptions {
  /// The load is applied in this many equal increments, each solved to equilibrium: from the
  /// force R̃(q₀) the initial guess carries (0 for q₀ = 0) to f̃. More steps help Newton through
  /// large deformations.
  int load_steps = 1;
  int max_iterations = 50;  ///< Newton iterations per load step.
  /// Converged when ‖R̃(q) − f̃‖₂ ≤ tolerance · max(‖f̃‖, ‖R̃(q₀)‖, 1e-12) (reduced force
  /// units): relative, as StaticSolveOptions::tolerance.
  double tolerance = 1e-8;
  /// Backtracking line search after each Newton step (halving up to 30 times), the rule of
  /// solve_static(): a step is taken once it decreases the potential energy E(q) − f̃ᵀq enough
  /// (Armijo) or the norm ‖R̃(q) − f̃‖.
  bool line_search = true;
  /// q₀, r entries; empty (the default) starts from q₀ = 0.
  Eigen::VectorXd initial_guess;
  /// Reports stage "reduced static solve", one unit per load step, and asks again after every
  /// Newton iteration; returning false cancels (Cancelled) within one iteration.
  ProgressCallback progress;

  /// @throws Error unless load_steps, max_iterations ≥ 1 and tolerance > 0 (finite).
  void validate() const;
};

/// Result of solve_reduced_static().
struct ReducedStaticSolution {
  Eigen::VectorXd coordinates;  ///< q with R̃(q) = f̃, r entries (always finite).
  int iterations = 0;           ///< Newton iterations over all load steps.
  double residual_norm = 0.0;   ///< Final ‖R̃(q) − f̃‖₂.
};

/// Solves R̃(q) = f̃ by Newton–Raphson with load stepping and line search, like solve_static()
/// for the full model. K̃(q) is factored densely by Cholesky; where it is not positive definite
/// (past a buckling or softening limit point) the Newton step uses the pseudo-inverse from its
/// eigendecomposition (|λ| ≤ 1e-12·max|λ| counted as zero), as make_reduced_newmark()'s integrator
/// does.
/// @param external_force f̃ (r entries, Uᵀ f for a full force f).
/// @throws Error for invalid options, sizes or non-finite input; SolverError, naming the load
///         step, iteration and residual, if Newton does not converge (e.g. a load above what a
///         softening model can carry) or values turn non-finite; Cancelled.
KHZ_REDUCED_API ReducedStaticSolution
solve_reduced_static(ReducedForceModel& forces, const Eigen::VectorXd& external_force,
                     const ReducedStaticOptions& options = {});

}  // namespace khz::reduced
