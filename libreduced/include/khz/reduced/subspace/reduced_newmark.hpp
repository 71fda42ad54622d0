#pragma once
// The implicit Newmark subspace integrator (thesis §2.9): the reduced model's runtime time
// stepping.

#include <khz/reduced/export.hpp>
#include <khz/reduced/solvers/newmark_parameters.hpp>
#include <khz/reduced/subspace/reduced_integrator.hpp>

#include <Eigen/Core>

#include <limits>
#include <memory>

namespace khz::reduced {

/// Options of make_reduced_newmark().
struct KHZ_REDUCED_API ReducedNewmarkOptions {
  NewmarkParameters newmark;  ///< Δt, β̃ (> 0: implicit), γ̃, Rayleigh α, β.
  /// j_max, Newton iterations per step. The thesis default 1 is the semi-implicit integrator:
  /// one linear solve per step, usually reported as iteration_limit.
  int max_newton_iterations = 1;
  /// Newton stops when ‖residual‖₂ ≤ tolerance · max(‖f̃‖, ‖R̃(q_i)‖, ‖M̃ q̈_i‖, f_floor) with
  /// f_floor = 1e-12 in reduced force units: relative to the forces at play at the start of
  /// the step, so the test is unit-free (as FullNewmarkOptions::tolerance). Under the
  /// acceleration limit the forces, like the residual, are scaled by s. Round-off bounds what
  /// is reachable: the residual sums inertia terms of size ‖M̃ q̇‖/(β̃Δt), so at Δt ≤ 1 ms a
  /// tolerance of 1e-12 can already be out of reach (the step then reports iteration_limit).
  double tolerance = 1e-9;
  /// Limit on ‖q̈‖₂ (units of q per s²) of thesis §3.10.2; +∞ (the default) disables it.
  /// Once per step, with the forces at the start of the step (q_i, q̇_i), the integrator computes
  /// the current acceleration q̈ = M̃⁻¹(f̃ − D̃ − R̃), D̃ = C̃(q_i) q̇_i, R̃ = R̃(q_i). If
  /// ‖q̈‖₂ > limit, it scales D̃, R̃ and f̃ by s = limit / ‖q̈‖₂ for this step: every Newton
  /// iteration solves M̃ q̈ + s (C̃ q̇ + R̃(q) − f̃) = 0, with the consistently scaled
  /// A = α1 M̃ + s (α4 C̃ + K̃). The step thus moves as if the mass were M̃ / s and starts with
  /// an acceleration of norm exactly `limit`; the end-of-step q̈ of a converged step is s times
  /// the end-of-step force balance, so it exceeds the limit only by as much as the forces
  /// change within the step. Moving as if the mass were M̃ / s, a limited step trades strain for
  /// kinetic energy at the rate s: the total falls by (1 − s)ΔE while the strain energy falls by
  /// ΔE, but would rise by (1 − s)ΔE while it rises, pumping energy into an object that swings
  /// back against the limit (a released 215° twist gained 3× its energy in 300 steps). So a
  /// limited step whose strain energy rose by ΔE > 0 also takes (1 − s)ΔE out of its kinetic
  /// energy, scaling q̇ (down to zero at most): limited steps never add energy beyond the work of
  /// the (scaled) external force. Limiting chops accelerations rather than following the
  /// physics: a safety net for haptics, where a quick push or the release of a strained object
  /// would otherwise produce accelerations the contact bounds do not expect.
  double acceleration_limit = std::numeric_limits<double>::infinity();

  /// @throws Error naming the first invalid option (Newmark parameters, β̃ = 0,
  ///         max_newton_iterations < 1, tolerance or acceleration_limit not positive).
  void validate() const;
};

/// Implicit Newmark time stepping of the reduced equations of motion
/// M̃ q̈ + C̃(q) q̇ + R̃(q) = f̃ (thesis eq. 2.21) with local Rayleigh damping C̃ = αM̃ + βK̃(q),
/// exactly the algorithm of thesis §2.9: q_{i+1} ← q_i, then up to j_max Newton iterations,
/// each evaluating R̃ and K̃ at q_{i+1}, forming A = α1 M̃ + α4 C̃ + K̃ and the residual
/// M̃(α1 Δq − α2 q̇_i − α3 q̈_i) + C̃(α4 Δq + α5 q̇_i + α6 q̈_i) + R̃ − f̃ (Δq = q_{i+1} − q_i),
/// stopping when the residual meets the tolerance, else solving A δ = −residual and updating
/// q_{i+1} += δ; finally q̇ and q̈ follow from Δq (α1…α6 of NewmarkConstants). Like the thesis,
/// A omits the derivative of the damping force's βK̃(q) with respect to q. A step's status is
/// iteration_limit when max_newton_iterations ran without meeting the tolerance.
///
/// The dense r×r system is solved by Cholesky; when A is not positive definite (a tangent
/// stiffness negative enough to beat the inertia term α1 M̃), by the symmetric
/// eigendecomposition with the true eigenvalues, eigenvalues with |λ| ≤ 1e-12·max|λ| treated as
/// zero (pseudo-inverse; ReducedStepReport::fallback_solve tells).
///
/// The integrator is used through ReducedIntegrator, which has the state, the mass, step()'s
/// contract and the error messages' prefix "ReducedNewmark".
/// @param forces the reduced force model (r coordinates); must outlive the integrator.
/// @param mass   M̃, r×r symmetric positive definite.
/// @returns an integrator at rest at q = 0, time 0.
/// @throws Error for invalid options or mass (naming the problem).
KHZ_REDUCED_API std::unique_ptr<ReducedIntegrator> make_reduced_newmark(
    ReducedForceModel& forces, const Eigen::MatrixXd& mass,
    const ReducedNewmarkOptions& options = {});

}  // namespace khz::reduced
