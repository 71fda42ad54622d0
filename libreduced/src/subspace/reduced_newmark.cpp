#include <khz/reduced/errors.hpp>
#include <khz/reduced/subspace/reduced_newmark.hpp>

#include "subspace/dense_symmetric_solve.hpp"
#include "subspace/reduced_state.hpp"
#include "subspace/scheme_integrator.hpp"

#include <algorithm>
#include <cmath>
#include <string>

namespace khz::reduced {

void ReducedNewmarkOptions::validate() const {
  NewmarkConstants::from(newmark);  // throws for invalid parameters and β̃ = 0
  if (max_newton_iterations < 1) {
    throw Error("ReducedNewmark: max_newton_iterations must be at least 1, got " +
                std::to_string(max_newton_iterations));
  }
  if (!(tolerance > 0) || !std::isfinite(tolerance)) {
    throw Error("ReducedNewmark: tolerance must be positive and finite, got " +
                std::to_string(tolerance));
  }
  if (!(acceleration_limit > 0)) {
    throw Error(
        "ReducedNewmark: acceleration_limit must be positive (+infinity disables it), got " +
        std::to_string(acceleration_limit));
  }
}

namespace {

/// The implicit Newmark scheme make_reduced_newmark() documents: its constants, its scratch and
/// its step.
struct NewmarkScheme : detail::StepWorkspace {
  NewmarkScheme(detail::ReducedState& shared, const ReducedNewmarkOptions& opts)
      : StepWorkspace(shared.q.size()),
        options(opts),
        constants(NewmarkConstants::from(opts.newmark)),
        state(shared),
        increment(shared.q.size()),
        residual(shared.q.size()),
        work(shared.q.size()) {}

  /// One step (ReducedIntegrator::advance() has the contract).
  ReducedStepReport advance(const Eigen::Ref<const Eigen::VectorXd>& external_force,
                            const Eigen::Ref<const Eigen::MatrixXd>* external_stiffness) noexcept;

  /// The scale s of §3.10.2 for this step (1 when the acceleration is within the limit), from the
  /// forces and stiffness evaluated at q_i.
  double acceleration_scale(const Eigen::Ref<const Eigen::VectorXd>& external_force) noexcept;

  /// Keeps a step limited by `scale` < 1 from adding energy (see
  /// ReducedNewmarkOptions::acceleration_limit): when the strain energy rose by ΔE > 0 from q_i to
  /// `next`, takes (1 − s)ΔE out of the kinetic energy of `velocity`.
  void remove_spurious_energy(double scale) noexcept;

  // The workspace's system is A, and its next, velocity and acceleration the current iterate's.
  ReducedNewmarkOptions options;
  NewmarkConstants constants;
  detail::ReducedState& state;  // the ReducedIntegrator's
  Eigen::VectorXd increment;    // Δq = q_{i+1} − q_i
  Eigen::VectorXd residual;     // then the Newton update
  Eigen::VectorXd work;
};

double NewmarkScheme::acceleration_scale(
    const Eigen::Ref<const Eigen::VectorXd>& external_force) noexcept {
  const NewmarkParameters& p = options.newmark;
  // Thesis §3.10.2: q̈ = M̃⁻¹(f̃ − D̃(q, q̇) − R̃(q)) at the current state, D̃ = C̃(q) q̇.
  work = external_force - forces;
  state.multiply_mass(state.velocity, residual);
  work -= p.mass_damping * residual;
  if (p.stiffness_damping != 0.0)
    work.noalias() -= p.stiffness_damping * (stiffness * state.velocity);
  state.solve_mass_in_place(work);
  const double norm = work.norm();
  // A non-finite norm is left to the residual test, which then fails the step.
  return norm > options.acceleration_limit ? options.acceleration_limit / norm : 1.0;
}

void NewmarkScheme::remove_spurious_energy(double scale) noexcept {
  const double spurious =
      (1.0 - scale) * (state.forces.energy(next) - state.forces.energy(state.q));
  if (!(spurious > 0.0)) return;
  state.multiply_mass(velocity, work);
  const double kinetic = 0.5 * velocity.dot(work);
  velocity *= kinetic > spurious ? std::sqrt(1.0 - spurious / kinetic) : 0.0;
}

ReducedStepReport NewmarkScheme::advance(
    const Eigen::Ref<const Eigen::VectorXd>& external_force,
    const Eigen::Ref<const Eigen::MatrixXd>* external_stiffness) noexcept {
  detail::ReducedState& s = state;
  ReducedStepReport report;

  const NewmarkConstants& c = constants;
  const NewmarkParameters& p = options.newmark;
  double scale = 1.0;  // of the forces, by the acceleration limit (§3.10.2)
  double tolerance = 0.0;
  bool converged = false;
  next = s.q;  // line 1
  for (int j = 0; j < options.max_newton_iterations; ++j) {
    // Lines 3-4. Non-finite forces or stiffness need no scan of their own: they reach the
    // residual norm or the solution, which are checked.
    s.forces.evaluate(next, forces, stiffness);
    if (j == 0) {
      if (std::isfinite(options.acceleration_limit)) {
        scale = acceleration_scale(external_force);
        report.acceleration_limited = scale < 1.0;
      }
      s.multiply_mass(s.acceleration, work);
      tolerance = options.tolerance * std::max({scale * external_force.norm(),
                                                scale * forces.norm(), work.norm(), 1e-12});
    }
    increment = next - s.q;
    acceleration = c.alpha1 * increment - c.alpha2 * s.velocity - c.alpha3 * s.acceleration;
    velocity = c.alpha4 * increment + c.alpha5 * s.velocity + c.alpha6 * s.acceleration;
    // Lines 8-9: M̃ q̈ + s (C̃ q̇ + R̃ − f̃) with C̃ = αM̃ + βK̃ (lines 5-6), s = 1 unless limited.
    work = acceleration + (scale * p.mass_damping) * velocity;
    s.multiply_mass(work, residual);
    if (p.stiffness_damping != 0.0) {
      residual.noalias() += (scale * p.stiffness_damping) * (stiffness * velocity);
    }
    residual += scale * (forces - external_force);
    // The external force at the iterate, f̃ − K̃ₑ (q − q_n).
    if (external_stiffness != nullptr) {
      residual.noalias() += scale * (*external_stiffness * increment);
    }
    report.residual_norm = residual.norm();
    if (!std::isfinite(report.residual_norm)) return report;
    if (report.residual_norm <= tolerance) {  // lines 10-11
      converged = true;
      break;
    }
    // Line 7: A = α1 M̃ + s (α4 C̃ + K̃) = (α1 + s α4 α) M̃ + s (1 + α4 β) K̃, plus s K̃ₑ.
    system = (scale * (1.0 + c.alpha4 * p.stiffness_damping)) * stiffness;
    s.add_scaled_mass(c.alpha1 + scale * c.alpha4 * p.mass_damping, system);
    if (external_stiffness != nullptr) system += scale * *external_stiffness;
    residual = -residual;  // lines 12-13: A δ = −residual
    const detail::DenseSolve solve = solver.solve_in_place(system, residual);
    if (solve == detail::DenseSolve::failed) return report;
    report.fallback_solve |= solve == detail::DenseSolve::eigen_fallback;
    next += residual;  // line 14
    report.iterations = j + 1;
  }
  // Lines 15-16.
  increment = next - s.q;
  velocity = c.alpha4 * increment + c.alpha5 * s.velocity + c.alpha6 * s.acceleration;
  acceleration = c.alpha1 * increment - c.alpha2 * s.velocity - c.alpha3 * s.acceleration;
  if (!next.allFinite() || !velocity.allFinite() || !acceleration.allFinite()) {
    return report;
  }
  if (scale < 1.0) remove_spurious_energy(scale);
  s.q = next;
  s.velocity = velocity;
  s.acceleration = acceleration;
  s.steps += 1;
  report.status = converged ? ReducedStepStatus::converged : ReducedStepStatus::iteration_limit;
  return report;
}

}  // namespace

std::unique_ptr<ReducedIntegrator> make_reduced_newmark(ReducedForceModel& forces,
                                                        const Eigen::MatrixXd& mass,
                                                        const ReducedNewmarkOptions& options) {
  options.validate();
  const NewmarkParameters& p = options.newmark;
  return std::make_unique<detail::SchemeIntegrator<NewmarkScheme>>(
      forces, mass, "ReducedNewmark", p.time_step, p.mass_damping, p.stiffness_damping, options);
}

}  // namespace khz::reduced
