#pragma once
// What every reduced time integrator offers (thesis §2.9): the interface the contact runtime,
// the tools and user code step deformable objects through, whichever scheme they chose.

#include <khz/reduced/export.hpp>
#include <khz/reduced/subspace/reduced_forces.hpp>
#include <khz/reduced/subspace/reduced_step_report.hpp>

#include <Eigen/Core>

#include <memory>
#include <string>

namespace khz::reduced {

namespace detail {
struct ReducedState;
}

/// A reduced integrator's state: what state() returns and set_state() takes.
struct ReducedIntegratorState {
  Eigen::VectorXd coordinates;   ///< q (r entries).
  Eigen::VectorXd velocity;      ///< q̇ (per s, r entries).
  Eigen::VectorXd acceleration;  ///< q̈ (per s², r entries).
  long steps = 0;                ///< Steps taken since the start: time() = steps × Δt.
};

/// Time stepping of the reduced equations of motion M̃ q̈ + C̃(q) q̇ + R̃(q) = f̃ (thesis eq.
/// 2.21) with Rayleigh damping C̃ = αM̃ + βK̃(q), over a ReducedForceModel with r coordinates.
/// make_reduced_newmark() (implicit, §2.9) and make_reduced_central_differences() (explicit,
/// §2.9.1) make one; the state, the mass and their checked setters are common and live here.
///
/// M̃ is any r×r symmetric positive definite matrix (the identity for a mass-orthonormal basis,
/// which the integrators detect and exploit). step() never throws and never allocates; the other
/// members may do both where they say so. Not thread-safe: an integrator drives a force model
/// with workspaces. Held through the std::unique_ptr the factories return: neither copyable nor
/// movable itself.
class KHZ_REDUCED_API ReducedIntegrator {
 public:
  virtual ~ReducedIntegrator();
  ReducedIntegrator(const ReducedIntegrator&) = delete;
  ReducedIntegrator& operator=(const ReducedIntegrator&) = delete;

  /// Advances one time step under the reduced external force f̃ (r entries, Uᵀ f for a full
  /// force f, N·m per unit q) held over the step. Never throws, never allocates; a failure
  /// (non-finite external force, forces, stiffness, solution or new state; a wrong-sized force,
  /// which also asserts in debug builds) is reported as ReducedStepStatus::failed and leaves the
  /// state exactly as it was. The scheme's own step (advance()) sees only forces that passed
  /// these checks.
  ReducedStepReport step(const Eigen::Ref<const Eigen::VectorXd>& external_force) noexcept;
  /// As step(external_force), for an external force that changes with q: over the step it is
  /// f̃ − K̃ₑ (q_{n+1} − q_n), with K̃ₑ = −∂f̃/∂q the `external_stiffness` (r×r, symmetric, N·m
  /// per unit q², e.g. a contact's stiffness projected on the modes). The implicit scheme takes
  /// it into its Newton iterations (a linearly implicit external force, stable where a stiff
  /// force held over the step makes the model ring); central differences evaluates the force at
  /// its explicit q_{n+1}. A zero matrix gives step(external_force). A wrong-sized or non-finite
  /// stiffness fails the step as a force does. Never throws, never allocates.
  ReducedStepReport step(const Eigen::Ref<const Eigen::VectorXd>& external_force,
                         const Eigen::Ref<const Eigen::MatrixXd>& external_stiffness) noexcept;

  Eigen::Index dimension() const noexcept;               ///< r.
  const Eigen::VectorXd& coordinates() const noexcept;   ///< q, r entries.
  const Eigen::VectorXd& velocity() const noexcept;      ///< q̇ (per s).
  const Eigen::VectorXd& acceleration() const noexcept;  ///< q̈ (per s²).
  const Eigen::MatrixXd& mass() const noexcept;          ///< M̃.
  double time_step() const noexcept;                     ///< Δt (s).
  double time() const noexcept;                          ///< Steps taken × Δt (s).
  double kinetic_energy() const noexcept;  ///< ½ q̇ᵀ M̃ q̇ (J); allocates nothing.
  double strain_energy() const noexcept;   ///< E(q) of the force model (J).

  /// q, q̇, q̈ and the step count (copies: allocates).
  ReducedIntegratorState state() const;
  /// Restores a state() (of this integrator or one of the same r). @throws Error (nothing
  /// changed) for wrong sizes, non-finite values or a negative step count.
  void set_state(const ReducedIntegratorState& state);
  /// Sets q, q̇, q̈ (r entries each), keeping the step count. @throws Error (nothing changed)
  /// for wrong sizes or non-finite values.
  void set_state(const Eigen::VectorXd& coordinates, const Eigen::VectorXd& velocity,
                 const Eigen::VectorXd& acceleration);
  /// Sets q and q̇ (r entries each) and the acceleration the equation of motion gives under
  /// `external_force` f̃: q̈ = M̃⁻¹(f̃ − R̃(q) − C̃(q) q̇). Starting from a consistent
  /// acceleration avoids the energy jump an arbitrary q̈₀ causes in the first step (and central
  /// differences need it, since q_{n+1} uses q̈_n). @throws Error for wrong sizes or non-finite
  /// input; SolverError if the model returns non-finite forces. Nothing changes on throw.
  void set_state_in_equilibrium(const Eigen::VectorXd& coordinates, const Eigen::VectorXd& velocity,
                                const Eigen::VectorXd& external_force);
  /// Back to the start: q = q̇ = q̈ = 0, time 0 (the rest shape, at rest). No allocation.
  void reset() noexcept;
  /// Replaces M̃ (e.g. after a density change); the state is kept (call
  /// set_state_in_equilibrium() for an acceleration consistent with the new mass).
  /// @throws Error (mass unchanged) unless r×r, finite, symmetric and positive definite.
  void set_mass(const Eigen::MatrixXd& mass);

 protected:
  /// @param name the class name that starts error messages.
  /// @param time_step Δt (s); @param mass_damping α (1/s); @param stiffness_damping β (s):
  ///        already validated by the derived class.
  /// @throws Error for a force model without coordinates or an invalid mass.
  ReducedIntegrator(ReducedForceModel& forces, const Eigen::MatrixXd& mass, std::string name,
                    double time_step, double mass_damping, double stiffness_damping);

  /// The shared state the derived step() reads and advances (libreduced's internal type).
  detail::ReducedState& shared_state() noexcept { return *m_state; }

 private:
  /// The scheme's step (the derived class's): as step(), with a finite force of r entries and,
  /// unless null, a finite r×r external stiffness.
  virtual ReducedStepReport advance(
      const Eigen::Ref<const Eigen::VectorXd>& external_force,
      const Eigen::Ref<const Eigen::MatrixXd>* external_stiffness) noexcept = 0;

  std::unique_ptr<detail::ReducedState> m_state;
};

}  // namespace khz::reduced
