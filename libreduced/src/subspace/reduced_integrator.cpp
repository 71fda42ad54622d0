#include <khz/reduced/errors.hpp>
#include <khz/reduced/subspace/reduced_integrator.hpp>

#include "subspace/reduced_state.hpp"

#include <cassert>
#include <utility>

namespace khz::reduced {

ReducedIntegrator::ReducedIntegrator(ReducedForceModel& forces, const Eigen::MatrixXd& mass,
                                     std::string name, double time_step, double mass_damping,
                                     double stiffness_damping)
    : m_state(std::make_unique<detail::ReducedState>(forces, mass, std::move(name), time_step,
                                                     mass_damping, stiffness_damping)) {}

ReducedIntegrator::~ReducedIntegrator() = default;

namespace {

/// Whether `force` is a finite vector of r entries, as both step()s require (a wrong size also
/// asserts in debug builds).
bool usable_force(const Eigen::Ref<const Eigen::VectorXd>& force, Eigen::Index r) noexcept {
  assert(force.size() == r && "external force must have r entries");
  return force.size() == r && force.allFinite();
}

}  // namespace

ReducedStepReport ReducedIntegrator::step(
    const Eigen::Ref<const Eigen::VectorXd>& external_force) noexcept {
  if (!usable_force(external_force, m_state->q.size())) return {};
  return advance(external_force, nullptr);
}

ReducedStepReport ReducedIntegrator::step(
    const Eigen::Ref<const Eigen::VectorXd>& external_force,
    const Eigen::Ref<const Eigen::MatrixXd>& external_stiffness) noexcept {
  const Eigen::Index r = m_state->q.size();
  assert(external_stiffness.rows() == r && external_stiffness.cols() == r &&
         "external stiffness must be r×r");
  if (!usable_force(external_force, r) || external_stiffness.rows() != r ||
      external_stiffness.cols() != r || !external_stiffness.allFinite()) {
    return {};
  }
  return advance(external_force, &external_stiffness);
}

Eigen::Index ReducedIntegrator::dimension() const noexcept { return m_state->q.size(); }
const Eigen::VectorXd& ReducedIntegrator::coordinates() const noexcept { return m_state->q; }
const Eigen::VectorXd& ReducedIntegrator::velocity() const noexcept { return m_state->velocity; }
const Eigen::VectorXd& ReducedIntegrator::acceleration() const noexcept {
  return m_state->acceleration;
}
const Eigen::MatrixXd& ReducedIntegrator::mass() const noexcept { return m_state->mass; }
double ReducedIntegrator::time_step() const noexcept { return m_state->time_step; }
double ReducedIntegrator::time() const noexcept {
  return static_cast<double>(m_state->steps) * m_state->time_step;
}
double ReducedIntegrator::kinetic_energy() const noexcept { return m_state->kinetic_energy(); }
double ReducedIntegrator::strain_energy() const noexcept { return m_state->strain_energy(); }

ReducedIntegratorState ReducedIntegrator::state() const {
  return {m_state->q, m_state->velocity, m_state->acceleration, m_state->steps};
}

void ReducedIntegrator::set_state(const ReducedIntegratorState& state) {
  if (state.steps < 0) {
    throw Error(m_state->owner + "::set_state: negative step count " + std::to_string(state.steps));
  }
  m_state->set_state(state.coordinates, state.velocity, state.acceleration);
  m_state->steps = state.steps;
}

void ReducedIntegrator::set_state(const Eigen::VectorXd& coordinates,
                                  const Eigen::VectorXd& velocity,
                                  const Eigen::VectorXd& acceleration) {
  m_state->set_state(coordinates, velocity, acceleration);
}

void ReducedIntegrator::set_state_in_equilibrium(const Eigen::VectorXd& coordinates,
                                                 const Eigen::VectorXd& velocity,
                                                 const Eigen::VectorXd& external_force) {
  m_state->set_state_in_equilibrium(coordinates, velocity, external_force);
}

void ReducedIntegrator::reset() noexcept {
  m_state->q.setZero();
  m_state->velocity.setZero();
  m_state->acceleration.setZero();
  m_state->steps = 0;
}

void ReducedIntegrator::set_mass(const Eigen::MatrixXd& mass) { m_state->set_mass(mass); }

}  // namespace khz::reduced
