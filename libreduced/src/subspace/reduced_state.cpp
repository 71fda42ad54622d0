#include "subspace/reduced_state.hpp"

#include <khz/reduced/errors.hpp>

#include <cmath>
#include <utility>

namespace khz::reduced::detail {
namespace {

/// Largest entry of |M̃ − I| for which M̃ counts as the identity.
constexpr double identity_tolerance = 1e-12;

}  // namespace

Eigen::LLT<Eigen::MatrixXd> factor_reduced_mass(const Eigen::MatrixXd& mass, Eigen::Index r,
                                                const std::string& owner) {
  if (mass.rows() != r || mass.cols() != r) {
    throw Error(owner + ": the reduced mass matrix must be " + std::to_string(r) + "×" +
                std::to_string(r) + ", got " + std::to_string(mass.rows()) + "×" +
                std::to_string(mass.cols()));
  }
  if (!mass.allFinite()) throw Error(owner + ": the reduced mass matrix has non-finite entries");
  const double largest = mass.cwiseAbs().maxCoeff();
  for (Eigen::Index j = 0; j < r; ++j) {
    for (Eigen::Index i = j + 1; i < r; ++i) {
      if (std::abs(mass(i, j) - mass(j, i)) > 1e-12 * largest) {
        throw Error(owner + ": the reduced mass matrix is not symmetric (entries (" +
                    std::to_string(i) + ", " + std::to_string(j) + ") and (" + std::to_string(j) +
                    ", " + std::to_string(i) + ") differ)");
      }
    }
  }
  Eigen::LLT<Eigen::MatrixXd> factor(mass);
  if (factor.info() != Eigen::Success) {
    throw Error(owner + ": the reduced mass matrix is not positive definite");
  }
  return factor;
}

ReducedState::ReducedState(ReducedForceModel& model, const Eigen::MatrixXd& reduced_mass,
                           std::string owner_name, double step, double alpha, double beta)
    : forces(model),
      owner(std::move(owner_name)),
      time_step(step),
      mass_damping(alpha),
      stiffness_damping(beta) {
  const Eigen::Index r = forces.dimension();
  if (r < 1) throw Error(owner + ": the force model has no reduced coordinates");
  assign_mass(reduced_mass, owner);
  q = Eigen::VectorXd::Zero(r);
  velocity = q;
  acceleration = q;
}

void ReducedState::set_state(const Eigen::VectorXd& coordinates, const Eigen::VectorXd& v,
                             const Eigen::VectorXd& a) {
  for (const Eigen::VectorXd* vector : {&coordinates, &v, &a}) {
    if (vector->size() != q.size()) {
      throw Error(owner + "::set_state: expected vectors of " + std::to_string(q.size()) +
                  " entries, got " + std::to_string(vector->size()));
    }
    if (!vector->allFinite()) throw Error(owner + "::set_state: non-finite state");
  }
  q = coordinates;
  velocity = v;
  acceleration = a;
}

void ReducedState::set_state_in_equilibrium(const Eigen::VectorXd& coordinates,
                                            const Eigen::VectorXd& v,
                                            const Eigen::VectorXd& external_force) {
  const Eigen::Index r = q.size();
  for (const Eigen::VectorXd* vector : {&coordinates, &v, &external_force}) {
    if (vector->size() != r) {
      throw Error(owner + "::set_state_in_equilibrium: expected vectors of " + std::to_string(r) +
                  " entries, got " + std::to_string(vector->size()));
    }
    if (!vector->allFinite()) throw Error(owner + "::set_state_in_equilibrium: non-finite input");
  }
  Eigen::VectorXd internal(r);
  Eigen::MatrixXd stiffness(r, r);
  forces.evaluate(coordinates, internal, stiffness);
  // M̃ q̈ = f̃ − R̃(q) − (αM̃ + βK̃(q)) q̇
  const Eigen::VectorXd net =
      external_force - internal - mass_damping * (mass * v) - stiffness_damping * (stiffness * v);
  const Eigen::VectorXd a = mass_factor.solve(net);
  if (!a.allFinite()) {
    throw SolverError(owner +
                      "::set_state_in_equilibrium: the force model returned non-finite values");
  }
  q = coordinates;
  velocity = v;
  acceleration = a;
}

void ReducedState::set_mass(const Eigen::MatrixXd& reduced_mass) {
  assign_mass(reduced_mass, owner + "::set_mass");
}

void ReducedState::assign_mass(const Eigen::MatrixXd& reduced_mass, const std::string& context) {
  mass_factor = factor_reduced_mass(reduced_mass, forces.dimension(), context);
  mass = reduced_mass;
  const Eigen::Index r = mass.rows();
  identity_mass =
      (mass - Eigen::MatrixXd::Identity(r, r)).cwiseAbs().maxCoeff() <= identity_tolerance;
}

void ReducedState::multiply_mass(const Eigen::VectorXd& x, Eigen::VectorXd& out) const noexcept {
  if (identity_mass) {
    out = x;
  } else {
    out.noalias() = mass * x;
  }
}

void ReducedState::solve_mass_in_place(Eigen::VectorXd& x) const noexcept {
  if (!identity_mass) mass_factor.solveInPlace(x);
}

void ReducedState::add_scaled_mass(double c, Eigen::MatrixXd& matrix) const noexcept {
  if (identity_mass) {
    matrix.diagonal().array() += c;
  } else {
    matrix += c * mass;
  }
}

double ReducedState::kinetic_energy() const noexcept {
  double twice = 0.0;
  for (Eigen::Index j = 0; j < velocity.size(); ++j) {
    twice += velocity(j) * mass.col(j).dot(velocity);
  }
  return 0.5 * twice;
}

double ReducedState::strain_energy() const noexcept { return forces.energy(q); }

}  // namespace khz::reduced::detail
