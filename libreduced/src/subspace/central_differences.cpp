#include <khz/reduced/errors.hpp>
#include <khz/reduced/solvers/newmark_parameters.hpp>
#include <khz/reduced/subspace/central_differences.hpp>

#include "subspace/dense_symmetric_solve.hpp"
#include "subspace/reduced_state.hpp"

#include <Eigen/Eigenvalues>

#include <cmath>
#include <limits>
#include <string>

namespace khz::reduced {

void ReducedCentralDifferencesOptions::validate() const {
  // Same ranges as the implicit integrator's parameters, at β̃ = 0, γ̃ = ½.
  NewmarkParameters{time_step, 0.0, 0.5, mass_damping, stiffness_damping}.validate();
}

struct ReducedCentralDifferences::Data : detail::StepWorkspace {
  Data(detail::ReducedState& shared, const ReducedCentralDifferencesOptions& opts)
      : StepWorkspace(shared.q.size()),
        options(opts),
        state(shared),
        predicted_velocity(shared.q.size()) {}

  /// acceleration = f̃ − R̃ − αM̃ q̇_pred: the net force before stiffness damping.
  void net_force(const Eigen::Ref<const Eigen::VectorXd>& external_force) noexcept {
    state.multiply_mass(predicted_velocity, velocity);  // velocity is free until the update
    acceleration = external_force - forces - options.mass_damping * velocity;
  }

  // The workspace's system is M̃ + ½Δt C̃ and its stiffness K̃(q_{n+1}), both used when β > 0.
  ReducedCentralDifferencesOptions options;
  detail::ReducedState& state;  // the ReducedIntegrator's (its heap object: moves keep it valid)
  Eigen::VectorXd predicted_velocity;  // q̇_n + ½Δt q̈_n
};

ReducedCentralDifferences::ReducedCentralDifferences(
    ReducedForceModel& forces, const Eigen::MatrixXd& mass,
    const ReducedCentralDifferencesOptions& options)
    : ReducedIntegrator(forces, mass, "ReducedCentralDifferences",
                        detail::validated(options).time_step, options.mass_damping,
                        options.stiffness_damping),
      m_data(std::make_unique<Data>(shared_state(), options)) {}
ReducedCentralDifferences::~ReducedCentralDifferences() = default;
ReducedCentralDifferences::ReducedCentralDifferences(ReducedCentralDifferences&&) noexcept =
    default;
ReducedCentralDifferences& ReducedCentralDifferences::operator=(
    ReducedCentralDifferences&&) noexcept = default;

ReducedStepReport ReducedCentralDifferences::advance(
    const Eigen::Ref<const Eigen::VectorXd>& external_force) noexcept {
  Data& d = *m_data;
  detail::ReducedState& s = d.state;
  ReducedStepReport report;

  const double h = d.options.time_step;
  const double alpha = d.options.mass_damping;
  const double beta = d.options.stiffness_damping;
  // Newmark with β̃ = 0, γ̃ = ½ (thesis §2.9.1): the displacement is explicit.
  d.next = s.q + h * s.velocity + (0.5 * h * h) * s.acceleration;
  d.predicted_velocity = s.velocity + (0.5 * h) * s.acceleration;
  // Equation of motion at n+1 with q̇_{n+1} = predicted + ½Δt q̈_{n+1}:
  // (M̃ + ½Δt C̃) q̈_{n+1} = f̃ − R̃ − C̃ · predicted.
  if (beta > 0.0) {
    s.forces.evaluate(d.next, d.forces, d.stiffness);
    if (!d.forces.allFinite() || !d.stiffness.allFinite()) return report;
    d.net_force(external_force);
    d.acceleration.noalias() -= beta * (d.stiffness * d.predicted_velocity);
    d.system = (0.5 * h * beta) * d.stiffness;
    s.add_scaled_mass(1.0 + 0.5 * h * alpha, d.system);
    const detail::DenseSolve solve = d.solver.solve_in_place(d.system, d.acceleration);
    if (solve == detail::DenseSolve::failed) return report;
    report.fallback_solve = solve == detail::DenseSolve::eigen_fallback;
  } else {
    s.forces.evaluate_forces(d.next, d.forces);
    if (!d.forces.allFinite()) return report;
    // C̃ = αM̃: the system matrix (1 + ½Δtα) M̃ reuses the mass factor.
    d.net_force(external_force);
    s.solve_mass_in_place(d.acceleration);
    d.acceleration /= 1.0 + 0.5 * h * alpha;
  }
  d.velocity = d.predicted_velocity + (0.5 * h) * d.acceleration;
  if (!d.next.allFinite() || !d.velocity.allFinite() || !d.acceleration.allFinite()) {
    return report;
  }
  s.q = d.next;
  s.velocity = d.velocity;
  s.acceleration = d.acceleration;
  s.steps += 1;
  report.status = ReducedStepStatus::converged;
  return report;
}

const ReducedCentralDifferencesOptions& ReducedCentralDifferences::options() const noexcept {
  return m_data->options;
}

double reduced_critical_time_step(ReducedForceModel& forces, const Eigen::MatrixXd& mass,
                                  const Eigen::VectorXd& q) {
  const Eigen::Index r = forces.dimension();
  const std::string owner = "reduced_critical_time_step";
  if (r < 1) throw Error(owner + ": the force model has no reduced coordinates");
  detail::factor_reduced_mass(mass, r, owner);
  if (q.size() != 0 && q.size() != r) {
    throw Error(owner + ": q must have " + std::to_string(r) +
                " entries (or none for q = 0), got " + std::to_string(q.size()));
  }
  if (!q.allFinite()) throw Error(owner + ": q is not finite");
  const Eigen::VectorXd at = q.size() == 0 ? Eigen::VectorXd::Zero(r) : q;
  Eigen::VectorXd internal(r);
  Eigen::MatrixXd stiffness(r, r);
  forces.evaluate(at, internal, stiffness);
  if (!stiffness.allFinite()) throw SolverError(owner + ": the stiffness K̃(q) is not finite");
  // K̃ x = ω² M̃ x; its largest eigenvalue is ω_max².
  const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> eigen(stiffness, mass,
                                                                        Eigen::EigenvaluesOnly);
  if (eigen.info() != Eigen::Success) {
    throw SolverError(owner + ": the eigenvalues of K̃(q) x = ω² M̃ x did not converge");
  }
  const double largest = eigen.eigenvalues().maxCoeff();
  return largest > 0.0 ? 2.0 / std::sqrt(largest) : std::numeric_limits<double>::infinity();
}

}  // namespace khz::reduced
