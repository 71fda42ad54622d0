#pragma once
// Explicit central-difference time stepping of a reduced model (thesis §2.9.1) and its stability
// limit.

#include <khz/reduced/export.hpp>
#include <khz/reduced/subspace/reduced_integrator.hpp>

#include <Eigen/Core>

#include <memory>

namespace khz::reduced {

/// Options of make_reduced_central_differences().
struct KHZ_REDUCED_API ReducedCentralDifferencesOptions {
  /// Δt (s), > 0. Stable near q only below reduced_critical_time_step() (for β = 0).
  double time_step = 1e-4;
  double mass_damping = 0.0;       ///< Rayleigh α (1/s), ≥ 0.
  double stiffness_damping = 0.0;  ///< Rayleigh β (s), ≥ 0; > 0 needs K̃(q) every step.

  /// @throws Error naming the first parameter out of range (or not finite).
  void validate() const;
};

/// Explicit Newmark time stepping (β̃ = 0, γ̃ = ½: central differences, thesis §2.9.1) of
/// M̃ q̈ + C̃(q) q̇ + R̃(q) = f̃ with Rayleigh damping C̃ = αM̃ + βK̃(q):
///   q_{n+1} = q_n + Δt q̇_n + ½Δt² q̈_n,
///   (M̃ + ½Δt C̃) q̈_{n+1} = f̃ − R̃(q_{n+1}) − C̃ (q̇_n + ½Δt q̈_n),   C̃ = C̃(q_{n+1}),
///   q̇_{n+1} = q̇_n + ½Δt (q̈_n + q̈_{n+1}).
/// The damping makes the update implicit in the velocity, hence the solve. Without stiffness
/// damping (β = 0) the matrix is (1 + ½Δtα) M̃, whose Cholesky factor is prepared once, and the
/// step evaluates R̃ only; with β > 0 it evaluates K̃ too and factors M̃ + ½Δt C̃ each step
/// (falling back to the pseudo-inverse through the eigendecomposition, like
/// make_reduced_newmark(), if a negative K̃ makes it indefinite). A successful step's status is
/// converged (iterations and residual_norm 0); an unstable step size ends as failed once the
/// growing state overflows.
///
/// As §2.9.1 explains, reduced models with modal derivatives have stiff high-frequency modes,
/// so this integrator needs far smaller steps than the implicit one; it is the reference for the
/// explicit-versus-implicit comparison. It is used through ReducedIntegrator, whose error
/// messages start "ReducedCentralDifferences".
/// @param forces the reduced force model (r coordinates); must outlive the integrator.
/// @param mass   M̃, r×r symmetric positive definite.
/// @returns an integrator at rest at q = 0, time 0 (set_state_in_equilibrium() gives the
///          consistent q̈ this scheme needs when starting elsewhere).
/// @throws Error for invalid options or mass (naming the problem).
KHZ_REDUCED_API std::unique_ptr<ReducedIntegrator> make_reduced_central_differences(
    ReducedForceModel& forces, const Eigen::MatrixXd& mass,
    const ReducedCentralDifferencesOptions& options = {});

/// The central-difference stability limit Δt_crit = 2 / ω_max of the undamped system linearized
/// at q, where ω_max² is the largest eigenvalue of K̃(q) x = ω² M̃ x (thesis §2.9.1). The thesis
/// writes the limit as 2π/ω, but 2π/ω is the period of the fastest mode: central differences on
/// an undamped linear system are stable exactly for ω_max Δt < 2 (amplification factor of
/// modulus 1), so 2/ω_max is what is implemented; the thesis's text also swaps the sides of the
/// eigenproblem. Stiffness damping lowers the limit further, to (2/ω)(√(1+ξ²) − ξ) with
/// ξ = βω/2; a stiffening model lowers it as it deforms (evaluate at the expected q).
/// @param forces the model (K̃ is evaluated once).
/// @param mass   M̃, r×r symmetric positive definite.
/// @param q      where to linearize, r entries; empty (the default) means q = 0.
/// @returns Δt_crit in s; +∞ when K̃(q) has no positive eigenvalue (nothing oscillates).
/// @throws Error for an invalid mass or q; SolverError if K̃(q) is not finite.
KHZ_REDUCED_API double reduced_critical_time_step(ReducedForceModel& forces,
                                                  const Eigen::MatrixXd& mass,
                                                  const Eigen::VectorXd& q = {});

}  // namespace khz::reduced
