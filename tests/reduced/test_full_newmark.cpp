#include <khz/reduced/errors.hpp>
#include <khz/reduced/solvers/full_newmark.hpp>
#include <khz/reduced/solvers/static_solver.hpp>
#include <khz/test/cantilever.hpp>
#include <khz/test/fixtures.hpp>
#include <khz/test/sanitizers.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

namespace khz::reduced {
namespace {

const Material steel = Material::stvk(200e9, 0.3, 7800.0);

/// A 1 m × 0.1 m × 0.1 m steel cantilever (80 hexahedra). Its first bending period is about
/// 12 ms, so Δt = 0.1 ms resolves it with ~120 steps.
test::Cantilever small_beam() { return test::Cantilever(1.0, 0.1, 2, steel); }

FullNewmarkOptions options_with(double time_step, double mass_damping = 0.0,
                                double stiffness_damping = 0.0) {
  FullNewmarkOptions options;
  options.newmark.time_step = time_step;
  options.newmark.mass_damping = mass_damping;
  options.newmark.stiffness_damping = stiffness_damping;
  return options;
}

/// Starts the beam from the static deflection under a 50 kN tip load (about 1 cm), at rest, and
/// lets go: the acceleration is the one the elastic forces alone give.
FullNewmark released_beam(const test::Cantilever& beam, const FullNewmarkOptions& options) {
  FullNewmark integrator(beam.model, beam.clamped, options);
  const StaticSolution bent =
      solve_static(beam.model, beam.clamped, beam.tip_load(Eigen::Vector3d(0, 0, -5e4)));
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(beam.model.num_dofs());
  integrator.set_state_in_equilibrium(bent.displacement, zero, zero);
  return integrator;
}

TEST(FullNewmark, UndampedEnergyDriftStaysBounded) {
  const test::Cantilever beam = small_beam();
  FullNewmark integrator = released_beam(beam, options_with(1e-4));
  const Eigen::VectorXd no_force = Eigen::VectorXd::Zero(beam.model.num_dofs());
  const double initial = integrator.strain_energy();
  double drift = 0.0;
  double min_strain = initial;
  // 8 periods; 1 under the sanitizers (the same code, one of CI's longest tests there).
  const int steps = test::sanitized_build ? 130 : 1000;
  for (int step = 0; step < steps; ++step) {
    const StepReport report = integrator.step(no_force);
    ASSERT_TRUE(report.converged) << "step " << step;
    const double energy = integrator.kinetic_energy() + integrator.strain_energy();
    drift = std::max(drift, std::abs(energy - initial) / initial);
    min_strain = std::min(min_strain, integrator.strain_energy());
  }
  // The beam really oscillates: strain energy passes near zero.
  EXPECT_LT(min_strain, 0.05 * initial);
  // Trapezoidal Newmark conserves the energy of linear systems exactly; the nonlinear terms and
  // the Newton tolerance leave a small bounded error. Measured: 5.4e-6 over 1000 steps (8
  // periods), less over 130; starting with ü₀ = 0 instead of the consistent acceleration
  // gave 2.9e-3.
  EXPECT_LT(drift, 2e-5);
}

TEST(FullNewmark, RayleighDampingDissipatesEnergy) {
  const test::Cantilever beam = small_beam();
  // Damping ratio ζ = α/2ω + βω/2 ≈ 0.05 in the first bending mode (ω ≈ 520 rad/s): the energy
  // falls to about e^(−2ζωt) ≈ 0.45 in 15 ms, 150 steps.
  FullNewmark integrator = released_beam(beam, options_with(1e-4, 1.0, 2e-4));
  const Eigen::VectorXd no_force = Eigen::VectorXd::Zero(beam.model.num_dofs());
  const double initial = integrator.strain_energy();
  double previous = initial;
  for (int step = 0; step < 150; ++step) {
    integrator.step(no_force);
    const double energy = integrator.kinetic_energy() + integrator.strain_energy();
    EXPECT_LE(energy, previous * (1 + 1e-9)) << "step " << step;
    previous = energy;
  }
  EXPECT_LT(previous, 0.5 * initial);
}

TEST(FullNewmark, HeavilyDampedMotionSettlesOnTheStaticSolution) {
  const test::Cantilever beam = small_beam();
  const Eigen::VectorXd load = beam.tip_load(Eigen::Vector3d(0, 2e4, -5e4));
  // Stiffness damping settles the high modes the time step cannot resolve (trapezoidal Newmark
  // has no numerical dissipation); mass damping settles the slow ones.
  FullNewmark integrator(beam.model, beam.clamped, options_with(1e-3, 2000.0, 1e-3));
  for (int step = 0; step < 200; ++step) integrator.step(load);
  const StaticSolution reference = solve_static(beam.model, beam.clamped, load);
  // Measured: relative difference 1.7e-9 after 200 steps of 1 ms.
  std::printf("settle %.3e\n", (integrator.displacement() - reference.displacement).norm() /
                                   reference.displacement.norm());
  EXPECT_LT((integrator.displacement() - reference.displacement).norm(),
            1e-8 * reference.displacement.norm());
  EXPECT_NEAR(integrator.time(), 0.2, 1e-12);
}

TEST(FullNewmark, SemiImplicitStepDoesOneNewtonIteration) {
  const test::Cantilever beam = small_beam();
  FullNewmarkOptions options = options_with(1e-4);
  options.max_newton_iterations = 1;
  FullNewmark integrator(beam.model, beam.clamped, options);
  const StepReport report = integrator.step(beam.tip_load(Eigen::Vector3d(0, 0, -1e4)));
  EXPECT_EQ(report.iterations, 1);
  EXPECT_FALSE(report.converged);
  EXPECT_LT(beam.tip_displacement(integrator.displacement()).z(), 0.0);
  for (int v : beam.clamped) EXPECT_EQ(integrator.displacement().segment<3>(3 * v).norm(), 0.0);
}

TEST(FullNewmark, IndefiniteSystemThrowsAndKeepsTheLastValidState) {
  const test::Cantilever beam = small_beam();
  FullNewmark integrator(beam.model, beam.clamped, options_with(1.0));
  // Crushed to 30 % in every direction, StVK's compressive stress makes K(u) indefinite, and a
  // one-second step leaves too little inertia (α1 M) to make the system matrix definite again.
  const Eigen::VectorXd crushed =
      -0.7 *
      Eigen::Map<const Eigen::VectorXd>(beam.model.mesh().vertices.data(), beam.model.num_dofs());
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(beam.model.num_dofs());
  integrator.set_state(crushed, zero, zero);
  const Eigen::VectorXd before = integrator.displacement();
  EXPECT_TRUE(test::throws_with_message<SolverError>(
      [&] { integrator.step(zero); },
      "FullNewmark: step 1: the system matrix is not positive definite at Newton iteration 0"));
  EXPECT_EQ(integrator.displacement(), before);
  EXPECT_EQ(integrator.time(), 0.0);
}

TEST(FullNewmark, RejectsBadInput) {
  const test::Cantilever beam = small_beam();
  EXPECT_THROW(FullNewmark(beam.model, beam.clamped, options_with(-1.0)), Error);
  FullNewmark integrator(beam.model, beam.clamped, options_with(1e-3));
  const Eigen::VectorXd wrong = Eigen::VectorXd::Zero(5);
  const Eigen::VectorXd right = Eigen::VectorXd::Zero(beam.model.num_dofs());
  EXPECT_THROW(integrator.step(wrong), Error);
  EXPECT_THROW(integrator.set_state(right, wrong, right), Error);
  Eigen::VectorXd nan = right;
  nan[7] = std::nan("");
  EXPECT_THROW(integrator.set_state(nan, right, right), Error);
}

}  // namespace
}  // namespace khz::reduced
