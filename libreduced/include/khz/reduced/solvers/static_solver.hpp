#pragma once
// Full-space nonlinear static equilibrium R(u) = f (thesis §2.1.10).

#include <khz/reduced/export.hpp>
#include <khz/reduced/fem/fem_model.hpp>
#include <khz/reduced/progress.hpp>

#include <Eigen/Core>

#include <span>

namespace khz::reduced {

/// Options of solve_static().
struct StaticSolveOptions {
  /// The load is applied in this many equal increments, each solved to equilibrium; more steps
  /// help Newton through large deformations.
  int load_steps = 1;
  int max_iterations = 50;  ///< Newton iterations per load step.
  /// Converged when ‖R(u) − f‖ ≤ tolerance · max(‖f‖, 1e-12 N) on the free dofs. Round-off
  /// limits what is reachable: ~4e-10 was measured for a 5k-hexahedron steel cantilever.
  double tolerance = 1e-8;
  /// Backtracking line search after each Newton step (halving up to 30 times): a step is taken
  /// once it decreases the potential energy W(u) − fᵀu enough (Armijo) or the norm ‖R(u) − f‖.
  bool line_search = true;
  /// Reports stage "static solve", one unit per load step, and asks again after every Newton
  /// iteration; returning false cancels (Cancelled) within one iteration.
  ProgressCallback progress;
};

/// Result of solve_static().
struct StaticSolution {
  Eigen::VectorXd displacement;  ///< u (m), 3n, zero at fixed vertices.
  int iterations = 0;            ///< Newton iterations over all load steps.
  double residual_norm = 0.0;    ///< Final ‖R(u) − f‖ on the free dofs (N).
};

/// Solves R(u) = f for u by Newton–Raphson with load stepping and line search; K(u) is factored
/// with CHOLMOD (LLᵀ, falling back to LDLᵀ where K is indefinite).
/// @param fixed_vertices vertices held at zero displacement; they must remove the rigid motions
///                       (e.g. 3 non-collinear vertices), or K is singular and SolverError follows.
/// @throws Error for invalid options or sizes; SolverError, naming the load step, iteration and
///         residual, if Newton does not converge or meets a singular system; Cancelled.
KHZ_REDUCED_API StaticSolution solve_static(const FemModel& model,
                                            std::span<const int> fixed_vertices,
                                            const Eigen::VectorXd& external_force,
                                            const StaticSolveOptions& options = {});

}  // namespace khz::reduced
