#pragma once
// Full-space (unreduced) implicit Newmark integrator: the reference every reduced simulation is
// measured against.

#include <khz/reduced/export.hpp>
#include <khz/reduced/fem/fem_model.hpp>
#include <khz/reduced/solvers/newmark_parameters.hpp>

#include <Eigen/Core>

#include <memory>
#include <span>

namespace khz::reduced {

/// Options of FullNewmark.
struct FullNewmarkOptions {
  NewmarkParameters newmark;                   ///< Δt, β̃, γ̃, Rayleigh α, β.
  MassLumping mass = MassLumping::consistent;  ///< Mass matrix used for inertia and damping.
  int max_newton_iterations = 10;              ///< j_max (1 = semi-implicit).
  /// Newton stops when ‖residual‖ ≤ tolerance · max(‖f_ext‖, ‖R(u_n)‖, ‖M a_n‖, f_floor), with
  /// f_floor = 1e-12 N: relative to the forces at play, so the test is unit-free.
  double tolerance = 1e-9;
};

/// Outcome of one FullNewmark::step().
struct StepReport {
  bool converged = false;      ///< Residual met the tolerance within max_newton_iterations.
  int iterations = 0;          ///< Newton iterations performed (solves).
  double residual_norm = 0.0;  ///< ‖residual‖ (N) when the step ended.
};

/// Implicit Newmark with Newton iterations (thesis §2.9, applied to the full model) and local
/// Rayleigh damping C = αM + βK(u) (eq. 2.33). Each Newton iteration assembles K(u) in place,
/// restricts it to the free dofs and factors A = (α1 + α4 α) M + (1 + α4 β) K(u) with CHOLMOD
/// (the symbolic analysis is done once). Fixed vertices have zero displacement.
class KHZ_REDUCED_API FullNewmark {
 public:
  /// @param model          the FEM model; must outlive the integrator.
  /// @param fixed_vertices vertices held at zero displacement (may be empty: unconstrained).
  /// @throws Error for invalid options or vertex indices.
  FullNewmark(const FemModel& model, std::span<const int> fixed_vertices,
              const FullNewmarkOptions& options = {});
  ~FullNewmark();
  FullNewmark(FullNewmark&&) noexcept;
  FullNewmark& operator=(FullNewmark&&) noexcept;

  /// Sets displacement, velocity and acceleration (each 3n; fixed dofs are zeroed).
  /// @throws Error for wrong sizes or non-finite values.
  void set_state(const Eigen::VectorXd& displacement, const Eigen::VectorXd& velocity,
                 const Eigen::VectorXd& acceleration);

  /// Sets displacement and velocity (3n each) and the acceleration the equation of motion gives
  /// under `external_force`: ü = M⁻¹(f − R(u) − C(u) u̇). Starting from a consistent acceleration
  /// avoids the energy jump an arbitrary ü₀ causes in the first step (e.g. releasing a deflected
  /// body with ü₀ = 0). @throws Error for wrong sizes or non-finite values.
  void set_state_in_equilibrium(const Eigen::VectorXd& displacement,
                                const Eigen::VectorXd& velocity,
                                const Eigen::VectorXd& external_force);

  /// Advances one time step under the external force (3n, N) held over the step.
  /// Non-convergence within max_newton_iterations is reported, not thrown.
  /// @throws SolverError if the iteration diverges (non-finite values, or the system matrix
  ///         cannot be factored); the state is then left as it was before the call.
  StepReport step(const Eigen::VectorXd& external_force);

  const Eigen::VectorXd& displacement() const noexcept;  ///< u (m), 3n.
  const Eigen::VectorXd& velocity() const noexcept;      ///< u̇ (m/s), 3n.
  const Eigen::VectorXd& acceleration() const noexcept;  ///< ü (m/s²), 3n.
  double time() const noexcept;                          ///< Steps taken × Δt (s).
  double kinetic_energy() const;                         ///< ½ u̇ᵀ M u̇ (J).
  double strain_energy() const;                          ///< Model strain energy at u (J).

 private:
  struct Data;
  std::unique_ptr<Data> m_data;
};

}  // namespace khz::reduced
