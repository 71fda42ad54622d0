#include <khz/reduced/errors.hpp>
#include <khz/reduced/subspace/reduced_static.hpp>
#include <khz/test/analytic_reduced_forces.hpp>
#include <khz/test/fixtures.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

namespace khz::reduced {
namespace {

using test::LinearReducedForces;
using test::SpringChainForces;

constexpr Eigen::Index links = 4;
constexpr double k = 100.0;
constexpr double kappa = 1e4;

/// A pull F on the chain's free end: every spring carries the tension F.
Eigen::VectorXd end_pull(double force) {
  Eigen::VectorXd load = Eigen::VectorXd::Zero(links);
  load(links - 1) = force;
  return load;
}

/// q_i = i·d for springs all stretched by d.
Eigen::VectorXd uniform_stretch(double d) {
  return Eigen::VectorXd::LinSpaced(links, 1.0, static_cast<double>(links)) * d;
}

/// The stiffening spring's elongation under tension F: the real root of κd³ + kd − F = 0
/// (Cardano; one real root since k, κ > 0).
double stiffening_elongation(double force) {
  const double p = k / kappa;
  const double half_q = -0.5 * force / kappa;
  const double root = std::sqrt(half_q * half_q + p * p * p / 27.0);
  return std::cbrt(-half_q + root) + std::cbrt(-half_q - root);
}

/// The softening spring's (kd − κd³) elongation under tension F below its peak: the root on the
/// stable branch [0, √(k / 3κ)], where the force increases, by bisection.
double softening_elongation(double force) {
  double low = 0.0;
  double high = std::sqrt(k / (3.0 * kappa));
  for (int i = 0; i < 200; ++i) {
    const double middle = 0.5 * (low + high);
    (k * middle - kappa * middle * middle * middle < force ? low : high) = middle;
  }
  return 0.5 * (low + high);
}

TEST(ReducedStatic, MatchesTheAnalyticEquilibriumOfAStiffeningChain) {
  SpringChainForces forces(links, k, kappa);
  const double force = 50.0;  // cubic term 2.3× the linear one
  const Eigen::VectorXd expected = uniform_stretch(stiffening_elongation(force));
  for (const int load_steps : {1, 4}) {
    ReducedStaticOptions options;
    options.load_steps = load_steps;
    options.tolerance = 1e-13;
    const ReducedStaticSolution solution = solve_reduced_static(forces, end_pull(force), options);
    // Measured 7e-16 (1 load step, 6 iterations) and 1.1e-15 (4 load steps, 20 iterations).
    EXPECT_LT((solution.coordinates - expected).norm(), 1e-14 * expected.norm()) << load_steps;
    EXPECT_LE(solution.residual_norm, 1e-13 * force);
    EXPECT_GE(solution.iterations, load_steps);
  }
}

TEST(ReducedStatic, SofteningChainBelowItsPeakSettlesOnTheStableBranch) {
  SpringChainForces forces(links, k, -kappa);
  const double peak = 2.0 / 3.0 * k * std::sqrt(k / (3.0 * kappa));  // 3.85
  const double force = 0.95 * peak;
  ReducedStaticOptions options;
  options.tolerance = 1e-13;  // near the peak K̃ is soft: q errors are 30× the residual's
  const ReducedStaticSolution solution = solve_reduced_static(forces, end_pull(force), options);
  const Eigen::VectorXd expected = uniform_stretch(softening_elongation(force));
  EXPECT_LT((solution.coordinates - expected).norm(), 1e-14 * expected.norm());  // 1.6e-16
}

TEST(ReducedStatic, ThrowsWhenTheLoadExceedsWhatASofteningChainCarries) {
  SpringChainForces forces(links, k, -kappa);
  const double peak = 2.0 / 3.0 * k * std::sqrt(k / (3.0 * kappa));
  ReducedStaticOptions options;
  options.load_steps = 3;  // 0.4, 0.8 and 1.2 times the peak: the last one fails
  try {
    solve_reduced_static(forces, end_pull(1.2 * peak), options);
    ADD_FAILURE() << "no SolverError";
  } catch (const SolverError& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("solve_reduced_static:"), std::string::npos) << message;
    EXPECT_NE(message.find("load step 3/3, Newton iteration"), std::string::npos) << message;
    EXPECT_NE(message.find("(residual "), std::string::npos) << message;
    EXPECT_EQ(message.find("nan"), std::string::npos) << message;
  }
}

TEST(ReducedStatic, SingularStiffnessUsesThePseudoInverse) {
  // K̃ = diag(2, 0): Cholesky fails; the load lies in the range, so q = K̃⁺ f̃ is the
  // minimum-norm equilibrium.
  LinearReducedForces forces(Eigen::Vector2d(2.0, 0.0).asDiagonal());
  const ReducedStaticSolution solution = solve_reduced_static(forces, Eigen::Vector2d(2.0, 0.0));
  EXPECT_EQ(solution.iterations, 1);
  EXPECT_LT((solution.coordinates - Eigen::Vector2d(1.0, 0.0)).norm(), 1e-15);
  // A load outside the range has no equilibrium: an error naming where it stopped, no NaN.
  EXPECT_TRUE(test::throws_with_message<SolverError>(
      [&] { solve_reduced_static(forces, Eigen::Vector2d(2.0, 1.0)); },
      "load step 1/1, Newton iteration 1 (residual 1)"));
}

TEST(ReducedStatic, StartsFromTheInitialGuessAndRampsFromItsForce) {
  SpringChainForces forces(links, k, kappa);
  const Eigen::VectorXd expected = uniform_stretch(stiffening_elongation(50.0));
  ReducedStaticOptions options;
  options.initial_guess = expected;
  const ReducedStaticSolution at_solution = solve_reduced_static(forces, end_pull(50.0), options);
  EXPECT_EQ(at_solution.iterations, 0);
  EXPECT_TRUE(at_solution.coordinates == expected);

  // From the equilibrium of 20 N to the one of 50 N in three load steps.
  options.initial_guess = uniform_stretch(stiffening_elongation(20.0));
  options.load_steps = 3;
  options.tolerance = 1e-13;
  const ReducedStaticSolution ramped = solve_reduced_static(forces, end_pull(50.0), options);
  EXPECT_LT((ramped.coordinates - expected).norm(), 1e-14 * expected.norm());
  EXPECT_GE(ramped.iterations, 3);
}

TEST(ReducedStatic, ReportsProgressAndCancels) {
  SpringChainForces forces(links, k, kappa);
  ReducedStaticOptions options;
  options.load_steps = 2;
  int reports = 0;
  std::int64_t last_done = -1;
  options.progress = [&](const Progress& progress) {
    EXPECT_EQ(progress.stage, "reduced static solve");
    EXPECT_EQ(progress.total, 2);
    EXPECT_GE(progress.done, last_done);
    last_done = progress.done;
    ++reports;
    return true;
  };
  const ReducedStaticSolution solution = solve_reduced_static(forces, end_pull(50.0), options);
  EXPECT_EQ(last_done, 2);
  EXPECT_EQ(reports, 1 + solution.iterations + 2);  // start, each iteration, each load step

  options.progress = [](const Progress& progress) { return progress.done == 0 && false; };
  EXPECT_THROW(solve_reduced_static(forces, end_pull(50.0), options), Cancelled);
}

TEST(ReducedStatic, RejectsInvalidInputAndNonFiniteModels) {
  SpringChainForces forces(links, k, kappa);
  const Eigen::VectorXd load = end_pull(1.0);
  EXPECT_TRUE(test::throws_with_message<Error>(
      [&] { solve_reduced_static(forces, Eigen::VectorXd::Zero(3)); },
      "solve_reduced_static: the force must have 4 finite entries"));
  Eigen::VectorXd not_finite = load;
  not_finite(0) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_TRUE(test::throws_with_message<Error>([&] { solve_reduced_static(forces, not_finite); },
                                               "4 finite entries"));
  for (const auto& change : {+[](ReducedStaticOptions& o) { o.load_steps = 0; },
                             +[](ReducedStaticOptions& o) { o.max_iterations = 0; },
                             +[](ReducedStaticOptions& o) { o.tolerance = 0.0; }}) {
    ReducedStaticOptions options;
    change(options);
    EXPECT_TRUE(test::throws_with_message<Error>(
        [&] { solve_reduced_static(forces, load, options); },
        "load_steps and max_iterations must be at least 1 and tolerance positive"));
  }
  ReducedStaticOptions wrong_guess;
  wrong_guess.initial_guess = Eigen::VectorXd::Zero(2);
  EXPECT_TRUE(
      test::throws_with_message<Error>([&] { solve_reduced_static(forces, load, wrong_guess); },
                                       "the initial guess must have 4 finite entries"));

  test::FaultyForces faulty(forces);
  faulty.poison_forces = true;
  EXPECT_TRUE(test::throws_with_message<SolverError>([&] { solve_reduced_static(faulty, load); },
                                                     "non-finite forces at the initial guess"));
  faulty.poison_forces = false;
  faulty.poison_stiffness = true;
  EXPECT_TRUE(test::throws_with_message<SolverError>([&] { solve_reduced_static(faulty, load); },
                                                     "no convergence at load step 1/1"));
}

}  // namespace
}  // namespace khz::reduced
