#pragma once
// The state, mass and set-up checks that ReducedNewmark and ReducedCentralDifferences share.

#include <khz/reduced/subspace/reduced_forces.hpp>

#include <Eigen/Cholesky>
#include <Eigen/Core>

#include <string>

namespace khz::reduced::detail {

/// Checks that `mass` is an r×r finite, symmetric (to round-off) and positive definite reduced
/// mass matrix M̃ and returns its Cholesky factor.
/// @throws Error starting with `owner` and naming the problem.
Eigen::LLT<Eigen::MatrixXd> factor_reduced_mass(const Eigen::MatrixXd& mass, Eigen::Index r,
                                                const std::string& owner);

/// Reduced coordinates q, velocities q̇, accelerations q̈ and the mass M̃ (with its factor) of a
/// reduced integrator over a force model, plus the checked setters both integrators expose.
struct ReducedState {
  /// @throws Error for a model of dimension 0 or an invalid mass.
  ReducedState(ReducedForceModel& model, const Eigen::MatrixXd& reduced_mass, std::string owner);

  /// @throws Error (nothing changed) for wrong sizes or non-finite values.
  void set_state(const Eigen::VectorXd& coordinates, const Eigen::VectorXd& velocity,
                 const Eigen::VectorXd& acceleration);
  /// Sets q, q̇ and q̈ = M̃⁻¹(f̃ − R̃(q) − C̃(q) q̇), C̃ = αM̃ + βK̃(q) (thesis eq. 2.21 with the
  /// damping of §2.9). @throws Error for wrong sizes or non-finite input, SolverError if the
  /// model returns non-finite values; nothing is changed then.
  void set_state_in_equilibrium(const Eigen::VectorXd& coordinates, const Eigen::VectorXd& velocity,
                                const Eigen::VectorXd& external_force, double mass_damping,
                                double stiffness_damping);
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
  std::string owner;  ///< Class name that starts error messages.
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

}  // namespace khz::reduced::detail
