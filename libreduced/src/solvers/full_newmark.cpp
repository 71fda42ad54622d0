#include <khz/reduced/errors.hpp>
#include <khz/reduced/solvers/fixed_dofs.hpp>
#include <khz/reduced/solvers/full_newmark.hpp>
#include <khz/reduced/solvers/sparse_cholesky.hpp>

#include "solvers/matrix_on_pattern.hpp"

#include <algorithm>
#include <string>

namespace khz::reduced {

struct FullNewmark::Data {
  Data(const FemModel& fem, std::span<const int> fixed_vertices, const FullNewmarkOptions& opts)
      : model(fem),
        fixed(fem.mesh().num_vertices(), fixed_vertices),
        options(opts),
        constants(NewmarkConstants::from(opts.newmark)),
        mass_full(fem.mass_matrix(opts.mass)),
        mass_free(fixed.restrict_matrix(mass_full)),
        stiffness_full(fem.stiffness_pattern()),
        stiffness_free(fixed.restrict_matrix(stiffness_full)),
        system(stiffness_free),
        mass_on_stiffness_pattern(detail::values_on_pattern(mass_free, stiffness_free)),
        u(Eigen::VectorXd::Zero(fem.num_dofs())),
        v(u),
        a(u) {
    if (options.max_newton_iterations < 1) {
      throw Error("FullNewmark: max_newton_iterations must be at least 1, got " +
                  std::to_string(options.max_newton_iterations));
    }
    if (!(options.tolerance > 0)) throw Error("FullNewmark: tolerance must be positive");
    solver.analyze(system);
  }

  const FemModel& model;
  FixedDofs fixed;
  FullNewmarkOptions options;
  NewmarkConstants constants;
  SparseMatrix mass_full, mass_free;
  SparseMatrix stiffness_full, stiffness_free;
  SparseMatrix system;  // A on the free dofs, with the stiffness pattern
  Eigen::VectorXd mass_on_stiffness_pattern;
  SparseCholesky solver;
  Eigen::VectorXd u, v, a;  // full state
  double time = 0.0;
  long steps = 0;
};

FullNewmark::FullNewmark(const FemModel& model, std::span<const int> fixed_vertices,
                         const FullNewmarkOptions& options)
    : m_data(std::make_unique<Data>(model, fixed_vertices, options)) {}
FullNewmark::~FullNewmark() = default;
FullNewmark::FullNewmark(FullNewmark&&) noexcept = default;
FullNewmark& FullNewmark::operator=(FullNewmark&&) noexcept = default;

void FullNewmark::set_state(const Eigen::VectorXd& displacement, const Eigen::VectorXd& velocity,
                            const Eigen::VectorXd& acceleration) {
  Data& d = *m_data;
  for (const Eigen::VectorXd* vector : {&displacement, &velocity, &acceleration}) {
    if (vector->size() != d.model.num_dofs()) {
      throw Error("FullNewmark::set_state: expected vectors of " +
                  std::to_string(d.model.num_dofs()) + " entries, got " +
                  std::to_string(vector->size()));
    }
    if (!vector->allFinite()) throw Error("FullNewmark::set_state: non-finite state");
  }
  // Round-tripping through the free dofs zeroes the fixed ones.
  d.fixed.expand_vector(d.fixed.restrict_vector(displacement), d.u);
  d.fixed.expand_vector(d.fixed.restrict_vector(velocity), d.v);
  d.fixed.expand_vector(d.fixed.restrict_vector(acceleration), d.a);
}

void FullNewmark::set_state_in_equilibrium(const Eigen::VectorXd& displacement,
                                           const Eigen::VectorXd& velocity,
                                           const Eigen::VectorXd& external_force) {
  Data& d = *m_data;
  set_state(displacement, velocity, external_force);  // validates sizes and finiteness
  const NewmarkParameters& p = d.options.newmark;
  Eigen::VectorXd forces_full;
  d.model.forces_and_stiffness(d.u, forces_full, d.stiffness_full);
  d.fixed.restrict_matrix_values(d.stiffness_full, d.stiffness_free);
  const Eigen::VectorXd v = d.fixed.restrict_vector(d.v);
  const Eigen::VectorXd net = d.fixed.restrict_vector(external_force - forces_full) -
                              p.mass_damping * (d.mass_free * v) -
                              p.stiffness_damping * (d.stiffness_free * v);
  SparseCholesky mass_solver;
  mass_solver.factorize(d.mass_free);
  d.fixed.expand_vector(mass_solver.solve(net), d.a);
}

StepReport FullNewmark::step(const Eigen::VectorXd& external_force) {
  Data& d = *m_data;
  if (external_force.size() != d.model.num_dofs()) {
    throw Error("FullNewmark::step: expected a force of " + std::to_string(d.model.num_dofs()) +
                " entries, got " + std::to_string(external_force.size()));
  }
  const NewmarkConstants& c = d.constants;
  const NewmarkParameters& p = d.options.newmark;
  const Eigen::VectorXd f = d.fixed.restrict_vector(external_force);
  const Eigen::VectorXd u0 = d.fixed.restrict_vector(d.u);
  const Eigen::VectorXd v0 = d.fixed.restrict_vector(d.v);
  const Eigen::VectorXd a0 = d.fixed.restrict_vector(d.a);

  Eigen::VectorXd u1 = u0;
  Eigen::VectorXd u1_full = d.u;
  Eigen::VectorXd forces_full;
  Eigen::VectorXd residual;
  Eigen::VectorXd acceleration, velocity;
  StepReport report;
  double scale = 0.0;
  // Thesis §2.9, applied to the full model: Newton on the dynamic equilibrium at t + Δt.
  for (int j = 0;; ++j) {
    d.model.forces_and_stiffness(u1_full, forces_full, d.stiffness_full);
    d.fixed.restrict_matrix_values(d.stiffness_full, d.stiffness_free);
    const Eigen::VectorXd du = u1 - u0;
    acceleration = c.alpha1 * du - c.alpha2 * v0 - c.alpha3 * a0;
    velocity = c.alpha4 * du + c.alpha5 * v0 + c.alpha6 * a0;
    // M ü + (αM + βK(u)) u̇ + R(u) − f, the damping being eq. 2.33.
    residual = d.mass_free * (acceleration + p.mass_damping * velocity) +
               p.stiffness_damping * (d.stiffness_free * velocity) +
               d.fixed.restrict_vector(forces_full) - f;
    report.residual_norm = residual.norm();
    if (j == 0) {
      scale = std::max({f.norm(), (residual + f).norm(), (d.mass_free * a0).norm(), 1e-12});
    }
    if (!std::isfinite(report.residual_norm)) {
      throw SolverError("FullNewmark: step " + std::to_string(d.steps + 1) +
                        " diverged at Newton " + "iteration " + std::to_string(j) +
                        " (non-finite residual)");
    }
    if (report.residual_norm <= d.options.tolerance * scale) {
      report.converged = true;
      break;
    }
    if (j == d.options.max_newton_iterations) break;

    // A = α1 M + α4 C + K(u) with C = αM + βK(u).
    detail::values_of(d.system) =
        (c.alpha1 + c.alpha4 * p.mass_damping) * d.mass_on_stiffness_pattern +
        (1.0 + c.alpha4 * p.stiffness_damping) * detail::values_of(d.stiffness_free);
    if (!d.solver.try_factorize(d.system)) {
      throw SolverError("FullNewmark: step " + std::to_string(d.steps + 1) +
                        ": the system matrix is not positive definite at Newton iteration " +
                        std::to_string(j) + " (residual " + std::to_string(report.residual_norm) +
                        " N); reduce the time step or the load");
    }
    u1 -= d.solver.solve(residual);
    d.fixed.expand_vector(u1, u1_full);
    report.iterations = j + 1;
  }
  // Velocities and accelerations follow from the final displacement (algorithm lines 15-16).
  const Eigen::VectorXd du = u1 - u0;
  d.fixed.expand_vector(c.alpha4 * du + c.alpha5 * v0 + c.alpha6 * a0, d.v);
  d.fixed.expand_vector(c.alpha1 * du - c.alpha2 * v0 - c.alpha3 * a0, d.a);
  d.u = u1_full;
  d.steps += 1;
  d.time = static_cast<double>(d.steps) * p.time_step;
  return report;
}

const Eigen::VectorXd& FullNewmark::displacement() const noexcept { return m_data->u; }
const Eigen::VectorXd& FullNewmark::velocity() const noexcept { return m_data->v; }
const Eigen::VectorXd& FullNewmark::acceleration() const noexcept { return m_data->a; }
double FullNewmark::time() const noexcept { return m_data->time; }

double FullNewmark::kinetic_energy() const {
  return 0.5 * m_data->v.dot(m_data->mass_full * m_data->v);
}

double FullNewmark::strain_energy() const { return m_data->model.strain_energy(m_data->u); }

}  // namespace khz::reduced
