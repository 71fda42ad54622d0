#include <khz/reduced/errors.hpp>
#include <khz/reduced/subspace/reduced_newmark.hpp>

#include "subspace/dense_symmetric_solve.hpp"
#include "subspace/reduced_state.hpp"

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

struct ReducedNewmark::Data : detail::StepWorkspace {
  Data(detail::ReducedState& shared, const ReducedNewmarkOptions& opts)
      : StepWorkspace(shared.q.size()),
        options(opts),
        constants(NewmarkConstants::from(opts.newmark)),
        state(shared),
        increment(shared.q.size()),
        residual(shared.q.size()),
        work(shared.q.size()) {}

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
  detail::ReducedState& state;  // the ReducedIntegrator's (its heap object: moves keep it valid)
  Eigen::VectorXd increment;    // Δq = q_{i+1} − q_i
  Eigen::VectorXd residual;     // then the Newton update
  Eigen::VectorXd work;
};

double ReducedNewmark::Data::acceleration_scale(
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

void ReducedNewmark::Data::remove_spurious_energy(double scale) noexcept {
  const double spurious =
      (1.0 - scale) * (state.forces.energy(next) - state.forces.energy(state.q));
  if (!(spurious > 0.0)) return;
  state.multiply_mass(velocity, work);
  const double kinetic = 0.5 * velocity.dot(work);
  velocity *= kinetic > spurious ? std::sqrt(1.0 - spurious / kinetic) : 0.0;
}

ReducedNewmark::ReducedNewmark(ReducedForceModel& forces, const Eigen::MatrixXd& mass,
                               const ReducedNewmarkOptions& options)
    : ReducedIntegrator(forces, mass, "ReducedNewmark",
                        detail::validated(options).newmark.time_step, options.newmark.mass_damping,
                        options.newmark.stiffness_damping),
      m_data(std::make_unique<Data>(shared_state(), options)) {}
ReducedNewmark::~ReducedNewmark() = default;
ReducedNewmark::ReducedNewmark(ReducedNewmark&&) noexcept = default;
ReducedNewmark& ReducedNewmark::operator=(ReducedNewmark&&) noexcept = default;

ReducedStepReport ReducedNewmark::advance(
    const Eigen::Ref<const Eigen::VectorXd>& external_force) noexcept {
  Data& d = *m_data;
  detail::ReducedState& s = d.state;
  ReducedStepReport report;

  const NewmarkConstants& c = d.constants;
  const NewmarkParameters& p = d.options.newmark;
  double scale = 1.0;  // of the forces, by the acceleration limit (§3.10.2)
  double tolerance = 0.0;
  bool converged = false;
  d.next = s.q;  // line 1
  for (int j = 0; j < d.options.max_newton_iterations; ++j) {
    // Lines 3-4. Non-finite forces or stiffness need no scan of their own: they reach the
    // residual norm or the solution, which are checked.
    s.forces.evaluate(d.next, d.forces, d.stiffness);
    if (j == 0) {
      if (std::isfinite(d.options.acceleration_limit)) {
        scale = d.acceleration_scale(external_force);
        report.acceleration_limited = scale < 1.0;
      }
      s.multiply_mass(s.acceleration, d.work);
      tolerance = d.options.tolerance * std::max({scale * external_force.norm(),
                                                  scale * d.forces.norm(), d.work.norm(), 1e-12});
    }
    d.increment = d.next - s.q;
    d.acceleration = c.alpha1 * d.increment - c.alpha2 * s.velocity - c.alpha3 * s.acceleration;
    d.velocity = c.alpha4 * d.increment + c.alpha5 * s.velocity + c.alpha6 * s.acceleration;
    // Lines 8-9: M̃ q̈ + s (C̃ q̇ + R̃ − f̃) with C̃ = αM̃ + βK̃ (lines 5-6), s = 1 unless limited.
    d.work = d.acceleration + (scale * p.mass_damping) * d.velocity;
    s.multiply_mass(d.work, d.residual);
    if (p.stiffness_damping != 0.0) {
      d.residual.noalias() += (scale * p.stiffness_damping) * (d.stiffness * d.velocity);
    }
    d.residual += scale * (d.forces - external_force);
    report.residual_norm = d.residual.norm();
    if (!std::isfinite(report.residual_norm)) return report;
    if (report.residual_norm <= tolerance) {  // lines 10-11
      converged = true;
      break;
    }
    // Line 7: A = α1 M̃ + s (α4 C̃ + K̃) = (α1 + s α4 α) M̃ + s (1 + α4 β) K̃.
    d.system = (scale * (1.0 + c.alpha4 * p.stiffness_damping)) * d.stiffness;
    s.add_scaled_mass(c.alpha1 + scale * c.alpha4 * p.mass_damping, d.system);
    d.residual = -d.residual;  // lines 12-13: A δ = −residual
    const detail::DenseSolve solve = d.solver.solve_in_place(d.system, d.residual);
    if (solve == detail::DenseSolve::failed) return report;
    report.fallback_solve |= solve == detail::DenseSolve::eigen_fallback;
    d.next += d.residual;  // line 14
    report.iterations = j + 1;
  }
  // Lines 15-16.
  d.increment = d.next - s.q;
  d.velocity = c.alpha4 * d.increment + c.alpha5 * s.velocity + c.alpha6 * s.acceleration;
  d.acceleration = c.alpha1 * d.increment - c.alpha2 * s.velocity - c.alpha3 * s.acceleration;
  if (!d.next.allFinite() || !d.velocity.allFinite() || !d.acceleration.allFinite()) {
    return report;
  }
  if (scale < 1.0) d.remove_spurious_energy(scale);
  s.q = d.next;
  s.velocity = d.velocity;
  s.acceleration = d.acceleration;
  s.steps += 1;
  report.status = converged ? ReducedStepStatus::converged : ReducedStepStatus::iteration_limit;
  return report;
}

const ReducedNewmarkOptions& ReducedNewmark::options() const noexcept { return m_data->options; }

}  // namespace khz::reduced
