#pragma once
// What one time step of a reduced integrator reports: real-time code returns a status, it does
// not throw.

namespace khz::reduced {

/// How a reduced time step ended.
enum class ReducedStepStatus {
  /// The step's equations were solved: the Newton residual met the tolerance (implicit), or the
  /// step's single linear solve succeeded (explicit).
  converged,
  /// All max_newton_iterations ran without the residual test passing; the state was advanced
  /// with the last iterate. The normal outcome of the semi-implicit default (one iteration).
  iteration_limit,
  /// Non-finite external force, forces, stiffness, solution or new state (or a wrong-sized
  /// external force): the state (q, q̇, q̈, time) is left exactly as it was before the step.
  failed,
};

/// Outcome of ReducedIntegrator::step() (make_reduced_newmark(),
/// make_reduced_central_differences()).
struct ReducedStepReport {
  ReducedStepStatus status = ReducedStepStatus::failed;
  /// Linear solves performed (Newton iterations; 0 for explicit steps or when the residual of
  /// the initial guess already met the tolerance).
  int iterations = 0;
  /// ‖residual‖₂ at the last residual test, in the units of the reduced forces (0 for explicit
  /// steps). The thesis algorithm evaluates no forces after its last update, so after
  /// iteration_limit this is the residual before the final Newton update.
  double residual_norm = 0.0;
  /// A system matrix was not positive definite and was solved through its eigendecomposition
  /// (pseudo-inverse) instead of by Cholesky.
  bool fallback_solve = false;
  /// The acceleration limit scaled this step's forces (ReducedNewmarkOptions::acceleration_limit).
  bool acceleration_limited = false;
};

}  // namespace khz::reduced
