#pragma once
// The state, mass and set-up checks that the implicit and explicit reduced integrators share.

#include <khz/reduced/subspace/reduced_forces.hpp>

#include "subspace/dense_symmetric_solve.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Core>

#include <string>

namespace khz::reduced::detail {

/// Checks that `mass` is an r×r finite, symmetric (to round-off) and positive definite reduced
/// mass matrix M̃ and returns its Cholesky factor.
/// @throws Error starting with `owner` and naming the problem.
Eigen::LLT<Eigen::MatrixXd> factor_reduced_mass(const Eigen::MatrixXd& mass, Eigen::Index r,
                                                const std::string& owner);

/// Reduced coordinates q, velocities q̇, accelerations q̈, the step count and the mass M̃ (with
/// its factor) of a reduced integrator over a force model, its Δt and Rayleigh damping, and the
/// checked setters of ReducedIntegrator.
struct ReducedState {
  /// @throws Error for a model of dimension 0 or an invalid mass.
  ReducedState(ReducedForceModel& model, const Eigen::MatrixXd& reduced_mass, std::string owner,
               double time_step, double mass_damping, double stiffness_damping);

  /// @throws Error (nothing changed) for wrong sizes or non-finite values.
  void set_state(const Eigen::VectorXd& coordinates, const Eigen::VectorXd& velocity,
                 const Eigen::VectorXd& acceleration);
  /// Sets q, q̇ and q̈ = M̃⁻¹(f̃ − R̃(q) − C̃(q) q̇), C̃ = αM̃ + βK̃(q) (thesis eq. 2.21 with the
  /// damping of §2.9). @throws Error for wrong sizes or non-finite input, SolverError if the
  /// model returns non-finite values; nothing is changed then.
  void set_state_in_equilibrium(const Eigen::VectorXd& coordinates, const Eigen::VectorXd& velocity,
                                const Eigen::VectorXd& external_force);
  /// @throws Error (mass unchanged) for an invalid mass.
  void set_mass(const Eigen::MatrixXd& reduced_mass);

  /// out = M̃ x (`out` must not be `x`).
  void multiply_mass(const Eigen::VectorXd& x, Eigen::VectorXd& out) const noexcept;
  /// x ← M̃⁻¹ x.
  void solve_mass_in_place(Eigen::VectorXd& x) const noexcept;
  /// matrix ← c M̃ + matrix.
  void add_scaled_mass(double c, Eigen::MatrixXd& matrix) const noexcept;

  double kinetic_energy() const noexcept;  ///< ½ q̇ᵀ M̃ q̇, without allocating.
  double strain_energy() const noexcept;   ///< E(q).

  ReducedForceModel& forces;
  std::string owner;         ///< Class name that starts error messages.
  double time_step;          ///< Δt (s).
  double mass_damping;       ///< Rayleigh α (1/s).
  double stiffness_damping;  ///< Rayleigh β (s).
  Eigen::MatrixXd mass;
  Eigen::LLT<Eigen::MatrixXd> mass_factor;
  /// M̃ is the identity to within 1e-12 per entry, as for a mass-orthonormal basis (thesis §2.9),
  /// and the mass helpers treat it as exactly I: no r×r products in a step.
  bool identity_mass = false;
  Eigen::VectorXd q, velocity, acceleration;
  long steps = 0;  ///< Steps taken; time = steps × Δt.

 private:
  /// Factors, stores and classifies a new mass. @throws Error starting with `context`.
  void assign_mass(const Eigen::MatrixXd& reduced_mass, const std::string& context);
};

/// The scratch every step of either scheme needs, sized once for r coordinates so that a step
/// allocates nothing: R̃ and K̃ at the new q, the dense system and its solver, and the new q, q̇,
/// q̈ before they are accepted.
struct StepWorkspace {
  explicit StepWorkspace(Eigen::Index r)
      : solver(r),
        forces(r),
        stiffness(r, r),
        system(r, r),
        next(r),
        velocity(r),
        acceleration(r) {}

  DenseSymmetricSolver solver;
  Eigen::VectorXd forces;        ///< R̃ at the new q.
  Eigen::MatrixXd stiffness;     ///< K̃ at the new q (when the scheme needs it).
  Eigen::MatrixXd system;        ///< The step's dense system matrix.
  Eigen::VectorXd next;          ///< q of the new state.
  Eigen::VectorXd velocity;      ///< q̇ of the new state.
  Eigen::VectorXd acceleration;  ///< q̈ of the new state.
};

}  // namespace khz::reduced::detail
