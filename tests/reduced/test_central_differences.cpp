#include <khz/reduced/errors.hpp>
#include <khz/reduced/subspace/central_differences.hpp>
#include <khz/reduced/subspace/reduced_newmark.hpp>
#include <khz/test/allocation_probe.hpp>
#include <khz/test/analytic_reduced_forces.hpp>
#include <khz/test/fixtures.hpp>

#include <gtest/gtest.h>
#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

namespace khz::reduced {
namespace {

using test::LinearReducedForces;
using test::SpringChainForces;

constexpr double nan = std::numeric_limits<double>::quiet_NaN();

ReducedCentralDifferencesOptions explicit_options(double time_step, double mass_damping = 0.0,
                                                  double stiffness_damping = 0.0) {
  ReducedCentralDifferencesOptions options;
  options.time_step = time_step;
  options.mass_damping = mass_damping;
  options.stiffness_damping = stiffness_damping;
  return options;
}

/// The chain's linear stiffness, k·[2 −1 0; −1 2 −1; 0 −1 1] with k = 100.
Eigen::MatrixXd chain_stiffness() {
  Eigen::Matrix3d stiffness;
  stiffness << 2, -1, 0, -1, 2, -1, 0, -1, 1;
  return 100.0 * stiffness;
}

const Eigen::Vector3d deflection(0.05, 0.15, 0.1);

TEST(ReducedCentralDifferences, CriticalTimeStepIsTwoOverTheLargestFrequency) {
  SpringChainForces linear(3, 100.0, 0.0);
  Eigen::MatrixXd mass(3, 3);
  mass << 2.0, 0.3, 0.0, 0.3, 1.0, 0.1, 0.0, 0.1, 0.5;
  // ω_max² independently: the largest eigenvalue of L⁻¹ K̃ L⁻ᵀ with M̃ = L Lᵀ.
  const Eigen::MatrixXd lower = mass.llt().matrixL();
  const Eigen::MatrixXd inverse = lower.inverse();
  const double largest = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(
                             inverse * chain_stiffness() * inverse.transpose())
                             .eigenvalues()
                             .maxCoeff();
  const double critical = reduced_critical_time_step(linear, mass);
  EXPECT_NEAR(critical, 2.0 / std::sqrt(largest), 1e-14 * critical);
  EXPECT_EQ(reduced_critical_time_step(linear, mass, Eigen::VectorXd::Zero(3)), critical);

  // A stiffening model needs smaller steps when deformed.
  SpringChainForces stiffening(3, 100.0, 1e4);
  EXPECT_EQ(reduced_critical_time_step(stiffening, mass), critical);
  EXPECT_LT(reduced_critical_time_step(stiffening, mass, deflection), 0.8 * critical);

  // Nothing oscillates without positive stiffness.
  LinearReducedForces unstable(-test::unit_mass(3));
  EXPECT_EQ(reduced_critical_time_step(unstable, mass), std::numeric_limits<double>::infinity());

  EXPECT_TRUE(test::throws_with_message<Error>(
      [&] { reduced_critical_time_step(linear, mass, Eigen::VectorXd::Zero(2)); },
      "reduced_critical_time_step: q must have 3 entries"));
  EXPECT_TRUE(test::throws_with_message<Error>([&] { reduced_critical_time_step(linear, -mass); },
                                               "not positive definite"));
}

/// ½ q̇ᵀq̇ + ½ qᵀ(K − Δt²/4 K²) q: what central differences conserve exactly for M̃ = I and a
/// linear K; positive definite exactly when Δt < 2/ω_max.
double modified_energy(const ReducedIntegrator& integrator, double time_step) {
  const Eigen::MatrixXd k = chain_stiffness();
  const Eigen::MatrixXd modified = k - 0.25 * time_step * time_step * k * k;
  const Eigen::VectorXd& q = integrator.coordinates();
  return 0.5 * integrator.velocity().squaredNorm() + 0.5 * q.dot(modified * q);
}

TEST(ReducedCentralDifferences, StableJustBelowTheCriticalStep) {
  SpringChainForces forces(3, 100.0, 0.0);
  const double step = 0.95 * reduced_critical_time_step(forces, test::unit_mass(3));
  const auto integrator =
      make_reduced_central_differences(forces, test::unit_mass(3), explicit_options(step));
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(3);
  integrator->set_state_in_equilibrium(deflection, zero, zero);
  const double initial = modified_energy(*integrator, step);
  double drift = 0.0;
  double largest = 0.0;
  for (int i = 0; i < 5000; ++i) {
    ASSERT_EQ(integrator->step(zero).status, ReducedStepStatus::converged);
    drift = std::max(drift, std::abs(modified_energy(*integrator, step) - initial) / initial);
    largest = std::max(largest, integrator->coordinates().norm());
  }
  // Measured drift 1.2e-13 over 5000 steps (~1500 periods of the fastest mode).
  EXPECT_LT(drift, 1e-12);
  // The conserved form is positive definite below the limit, which bounds the motion:
  // ‖q‖² ≤ 2 H / μ_min with μ_min its smallest eigenvalue.
  const Eigen::MatrixXd k = chain_stiffness();
  const double smallest =
      Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(k - 0.25 * step * step * k * k)
          .eigenvalues()
          .minCoeff();
  ASSERT_GT(smallest, 0.0);
  EXPECT_LE(largest, std::sqrt(2.0 * initial / smallest));
}

TEST(ReducedCentralDifferences, DivergesJustAboveTheCriticalStepUntilItReportsFailure) {
  SpringChainForces forces(3, 100.0, 0.0);
  const double critical = reduced_critical_time_step(forces, test::unit_mass(3));
  const double step = 1.05 * critical;
  const auto integrator =
      make_reduced_central_differences(forces, test::unit_mass(3), explicit_options(step));
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(3);
  integrator->set_state_in_equilibrium(deflection, zero, zero);
  // The fastest mode's amplification factor: the root of λ² − (2 − x²) λ + 1 = 0 of largest
  // modulus, x = ω_max Δt = 2.1.
  const double x = 2.0 * step / critical;
  const double b = 2.0 - x * x;
  const double growth = std::abs(b - std::sqrt(b * b - 4.0)) / 2.0;  // 1.877
  for (int i = 0; i < 200; ++i) integrator->step(zero);
  const double before = integrator->coordinates().norm();
  for (int i = 0; i < 100; ++i) integrator->step(zero);
  const double measured = std::pow(integrator->coordinates().norm() / before, 0.01);
  EXPECT_NEAR(measured, growth, 1e-9 * growth);

  // It grows until the state would overflow (measured: at step 1124); that step fails and keeps
  // the last finite state.
  int steps = 300;
  ReducedStepReport report;
  Eigen::VectorXd last = integrator->coordinates();
  for (; steps < 2000; ++steps) {
    last = integrator->coordinates();
    report = integrator->step(zero);
    if (report.status == ReducedStepStatus::failed) break;
  }
  EXPECT_EQ(report.status, ReducedStepStatus::failed);
  EXPECT_TRUE(integrator->coordinates() == last);
  EXPECT_TRUE(integrator->coordinates().allFinite());
  EXPECT_DOUBLE_EQ(integrator->time(), steps * step);
}

/// q at t = 0.2 s of the stiffening chain under a load, explicit and implicit (converged).
Eigen::VectorXd explicit_minus_implicit(int steps, double mass_damping, double stiffness_damping) {
  SpringChainForces forces(3, 100.0, 1e4);
  const double step = 0.2 / steps;
  const auto explicit_integrator = make_reduced_central_differences(
      forces, test::unit_mass(3), explicit_options(step, mass_damping, stiffness_damping));
  ReducedNewmarkOptions implicit_options;
  implicit_options.newmark.time_step = step;
  implicit_options.newmark.mass_damping = mass_damping;
  implicit_options.newmark.stiffness_damping = stiffness_damping;
  implicit_options.max_newton_iterations = 20;
  implicit_options.tolerance = 1e-10;  // 1e-12 is round-off at Δt = 0.5 ms
  const auto implicit_integrator =
      make_reduced_newmark(forces, test::unit_mass(3), implicit_options);
  const Eigen::VectorXd load = Eigen::Vector3d(0.0, 5.0, 10.0);
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(3);
  explicit_integrator->set_state_in_equilibrium(deflection, zero, load);
  implicit_integrator->set_state_in_equilibrium(deflection, zero, load);
  for (int i = 0; i < steps; ++i) {
    EXPECT_EQ(explicit_integrator->step(load).status, ReducedStepStatus::converged);
    EXPECT_EQ(implicit_integrator->step(load).status, ReducedStepStatus::converged);
  }
  return explicit_integrator->coordinates() - implicit_integrator->coordinates();
}

TEST(ReducedCentralDifferences, MatchesTheImplicitIntegratorForSmallSteps) {
  // Both are second-order discretizations of the same equations, so their difference shrinks
  // 4× per halving of Δt: with and without the damping (β > 0 takes the factored path).
  for (const auto& [alpha, beta] : {std::pair{0.0, 0.0}, std::pair{0.5, 0.002}}) {
    const double coarse = explicit_minus_implicit(200, alpha, beta).norm();
    const double fine = explicit_minus_implicit(400, alpha, beta).norm();
    EXPECT_LT(fine, 1e-4 * deflection.norm());
    EXPECT_NEAR(coarse / fine, 4.0, 0.1);
  }
}

TEST(ReducedCentralDifferences, IndefiniteDampedSystemIsSolvedThroughTheEigenFallback) {
  // M̃ + ½Δt β K̃ with K̃ = diag(100, 100, −1e5), Δt = 0.01 s, β = 0.01 s has a −4 entry.
  const Eigen::MatrixXd stiffness = Eigen::Vector3d(100.0, 100.0, -1e5).asDiagonal();
  LinearReducedForces forces(stiffness);
  const double h = 0.01;
  const double beta = 0.01;
  const auto integrator =
      make_reduced_central_differences(forces, test::unit_mass(3), explicit_options(h, 0.0, beta));
  const Eigen::VectorXd q0 = Eigen::Vector3d(0.1, -0.2, 0.3);
  const Eigen::VectorXd v0 = Eigen::Vector3d(1.0, 0.0, -1.0);
  const Eigen::VectorXd a0 = Eigen::Vector3d(0.5, 0.5, 0.0);
  const Eigen::VectorXd load = Eigen::Vector3d(1.0, 2.0, 3.0);
  integrator->set_state(q0, v0, a0);
  const ReducedStepReport report = integrator->step(load);
  EXPECT_TRUE(report.fallback_solve);
  EXPECT_EQ(report.status, ReducedStepStatus::converged);
  // Independently: (I + ½hβK̃) q̈₁ = f̃ − K̃ q₁ − βK̃ (q̇₀ + ½h q̈₀), by a dense QR.
  const Eigen::VectorXd q1 = q0 + h * v0 + 0.5 * h * h * a0;
  const Eigen::VectorXd predicted = v0 + 0.5 * h * a0;
  const Eigen::MatrixXd system = test::unit_mass(3) + 0.5 * h * beta * stiffness;
  const Eigen::VectorXd a1 =
      system.colPivHouseholderQr().solve(load - stiffness * q1 - beta * (stiffness * predicted));
  EXPECT_LT((integrator->acceleration() - a1).norm(), 1e-13 * a1.norm());
  EXPECT_LT((integrator->coordinates() - q1).norm(), 1e-15);
}

TEST(ReducedCentralDifferences, NonFiniteValuesFailTheStepAndKeepTheState) {
  SpringChainForces chain(3, 100.0, 1e4);
  test::FaultyForces forces(chain);
  for (const double beta : {0.0, 0.001}) {
    const auto integrator = make_reduced_central_differences(forces, test::unit_mass(3),
                                                             explicit_options(1e-3, 0.1, beta));
    const Eigen::VectorXd load = Eigen::Vector3d(0.0, 1.0, 2.0);
    integrator->set_state_in_equilibrium(deflection, Eigen::VectorXd::Zero(3), load);
    integrator->step(load);
    const Eigen::VectorXd q = integrator->coordinates();
    const Eigen::VectorXd v = integrator->velocity();
    const Eigen::VectorXd a = integrator->acceleration();
    const auto expect_unchanged = [&] {
      EXPECT_TRUE(integrator->coordinates() == q && integrator->velocity() == v &&
                  integrator->acceleration() == a);
      EXPECT_DOUBLE_EQ(integrator->time(), 1e-3);
    };
    forces.poison_forces = true;
    EXPECT_EQ(integrator->step(load).status, ReducedStepStatus::failed) << "β = " << beta;
    expect_unchanged();
    forces.poison_forces = false;
    if (beta > 0.0) {  // K̃ is evaluated only with stiffness damping
      forces.poison_stiffness = true;
      EXPECT_EQ(integrator->step(load).status, ReducedStepStatus::failed);
      expect_unchanged();
      forces.poison_stiffness = false;
    }
    Eigen::VectorXd bad_load = load;
    bad_load(2) = nan;
    EXPECT_EQ(integrator->step(bad_load).status, ReducedStepStatus::failed);
    expect_unchanged();
    EXPECT_EQ(integrator->step(load).status, ReducedStepStatus::converged);
  }
}

TEST(ReducedCentralDifferences, AStepAllocatesNothing) {
  SpringChainForces chain(40, 100.0, 1e4);  // r = 40: Eigen's blocked Cholesky path
  const auto plain =
      make_reduced_central_differences(chain, test::unit_mass(40), explicit_options(1e-3, 0.5));
  const auto damped = make_reduced_central_differences(chain, test::unit_mass(40),
                                                       explicit_options(1e-3, 0.5, 0.001));
  const Eigen::VectorXd load = Eigen::VectorXd::Constant(40, 1.0);
  // Without malloc counting (sanitizer builds) this still counts operator new.
  test::allocation_count = 0;
  double energy = 0.0;
  for (int i = 0; i < 5; ++i) {
    EXPECT_EQ(plain->step(load).status, ReducedStepStatus::converged);
    EXPECT_EQ(damped->step(load).status, ReducedStepStatus::converged);
    energy += plain->kinetic_energy() + damped->strain_energy();
  }
  EXPECT_EQ(test::allocation_count.load(), 0u);
  EXPECT_GT(energy, 0.0);
}

TEST(ReducedCentralDifferences, RejectsInvalidOptionsAndMasses) {
  SpringChainForces forces(3, 100.0, 0.0);
  const auto construct = [&](const ReducedCentralDifferencesOptions& options,
                             const Eigen::MatrixXd& mass) {
    return [&forces, options, mass] {
      const auto integrator = make_reduced_central_differences(forces, mass, options);
    };
  };
  EXPECT_TRUE(test::throws_with_message<Error>(construct(explicit_options(0.0), test::unit_mass(3)),
                                               "time_step"));
  EXPECT_TRUE(test::throws_with_message<Error>(
      construct(explicit_options(1e-3, -1.0), test::unit_mass(3)), "mass_damping"));
  EXPECT_TRUE(test::throws_with_message<Error>(
      construct(explicit_options(1e-3, 0.0, nan), test::unit_mass(3)), "stiffness_damping"));
  EXPECT_TRUE(test::throws_with_message<Error>(
      construct(explicit_options(1e-3), test::unit_mass(4)),
      "ReducedCentralDifferences: the reduced mass matrix must be 3×3, got 4×4"));
  const auto integrator = make_reduced_central_differences(forces, test::unit_mass(3));
  EXPECT_TRUE(test::throws_with_message<Error>([&] { integrator->set_mass(-test::unit_mass(3)); },
                                               "ReducedCentralDifferences::set_mass"));
  integrator->set_mass(2.0 * test::unit_mass(3));
  integrator->set_state(Eigen::VectorXd::Zero(3), Eigen::Vector3d(1.0, 0.0, 0.0),
                        Eigen::VectorXd::Zero(3));
  EXPECT_DOUBLE_EQ(integrator->kinetic_energy(), 1.0);
}

}  // namespace
}  // namespace khz::reduced
