// ReducedIntegrator: both schemes driven through the one interface the runtime uses, its state
// round trip, reset, and the checks its setters share.
#include <khz/reduced/errors.hpp>
#include <khz/reduced/subspace/central_differences.hpp>
#include <khz/reduced/subspace/reduced_integrator.hpp>
#include <khz/reduced/subspace/reduced_newmark.hpp>
#include <khz/test/allocation_probe.hpp>
#include <khz/test/analytic_reduced_forces.hpp>
#include <khz/test/fixtures.hpp>
#include <khz/test/newmark_options.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

namespace khz::reduced {
namespace {

using test::SpringChainForces;
using test::throws_with_message;

/// A stiffening three-spring chain, one force model per integrator (models keep workspaces).
struct Chains {
  SpringChainForces implicit_chain{3, 100.0, 1e4};
  SpringChainForces explicit_chain{3, 100.0, 1e4};
};

std::vector<std::unique_ptr<ReducedIntegrator>> both_schemes(Chains& chains) {
  ReducedCentralDifferencesOptions explicit_options;
  explicit_options.time_step = 1e-3;  // below the critical step at these deflections
  explicit_options.mass_damping = 0.5;
  std::vector<std::unique_ptr<ReducedIntegrator>> integrators;
  integrators.push_back(make_reduced_newmark(chains.implicit_chain, Eigen::MatrixXd::Identity(3, 3),
                                             test::trapezoidal_options(1e-3, 3, 1e-12, 0.5)));
  integrators.push_back(make_reduced_central_differences(
      chains.explicit_chain, Eigen::MatrixXd::Identity(3, 3), explicit_options));
  return integrators;
}

const Eigen::Vector3d push(0.0, 0.0, 3.0);

// Through the interface, each scheme gives exactly what the concrete class gives (one step()
// body, reached by one virtual call), and state() / set_state() restore a trajectory bit for bit.
TEST(ReducedIntegrator, StateRoundTripRestoresTheTrajectory) {
  Chains chains;
  for (const std::unique_ptr<ReducedIntegrator>& integrator : both_schemes(chains)) {
    ReducedIntegrator& base = *integrator;
    for (int i = 0; i < 20; ++i) ASSERT_NE(base.step(push).status, ReducedStepStatus::failed);
    const ReducedIntegratorState saved = base.state();
    EXPECT_EQ(saved.steps, 20);
    EXPECT_DOUBLE_EQ(base.time(), 20 * base.time_step());
    std::vector<Eigen::VectorXd> first;
    for (int i = 0; i < 10; ++i) {
      base.step(push);
      first.push_back(base.coordinates());
    }
    base.set_state(saved);
    EXPECT_EQ(base.time(), saved.steps * base.time_step());
    for (int i = 0; i < 10; ++i) {
      base.step(push);
      EXPECT_EQ(base.coordinates(), first[static_cast<std::size_t>(i)]) << "step " << i;
    }
    EXPECT_GT(base.coordinates().norm(), 1e-3);  // the push moved it
  }
}

TEST(ReducedIntegrator, ResetReturnsToRestAtTimeZeroWithoutAllocating) {
  Chains chains;
  for (const std::unique_ptr<ReducedIntegrator>& integrator : both_schemes(chains)) {
    for (int i = 0; i < 5; ++i) integrator->step(push);
    ASSERT_GT(integrator->velocity().norm(), 0.0);
    const Eigen::VectorXd no_force = Eigen::VectorXd::Zero(3);
    test::allocation_count = 0;
    integrator->reset();
    const ReducedStepReport report = integrator->step(no_force);
    EXPECT_EQ(test::allocation_count, 0u);
    EXPECT_NE(report.status, ReducedStepStatus::failed);
    // At rest at the rest shape under no force, a step stays there.
    EXPECT_EQ(integrator->coordinates(), Eigen::Vector3d::Zero());
    EXPECT_EQ(integrator->velocity(), Eigen::Vector3d::Zero());
    EXPECT_DOUBLE_EQ(integrator->time(), integrator->time_step());
    EXPECT_EQ(integrator->kinetic_energy(), 0.0);
    EXPECT_EQ(integrator->strain_energy(), 0.0);
  }
}

// An external force that changes with q, f̃ − K̃ₑ (q − q_n): after each step both schemes'
// states satisfy the equation of motion with that force at the new q, M̃ q̈ + α M̃ q̇ + R̃(q) =
// f̃ − K̃ₑ (q_{n+1} − q_n), evaluated here from the chain's own forces; and the step allocates
// nothing.
TEST(ReducedIntegrator, ExternalStiffnessActsAtTheNewCoordinates) {
  Chains chains;
  SpringChainForces reference_chain{3, 100.0, 1e4};
  Eigen::Matrix3d external_stiffness;
  external_stiffness << 400.0, -50.0, 0.0, -50.0, 300.0, 20.0, 0.0, 20.0, 250.0;
  for (const std::unique_ptr<ReducedIntegrator>& integrator : both_schemes(chains)) {
    for (int i = 0; i < 30; ++i) {
      const Eigen::VectorXd before = integrator->coordinates();
      test::allocation_count = 0;
      const ReducedStepReport report = integrator->step(push, external_stiffness);
      EXPECT_EQ(test::allocation_count, 0u);
      ASSERT_EQ(report.status, ReducedStepStatus::converged);
      const Eigen::VectorXd& q = integrator->coordinates();
      Eigen::VectorXd forces(3);
      reference_chain.evaluate_forces(q, forces);
      const Eigen::VectorXd residual = integrator->acceleration() + 0.5 * integrator->velocity() +
                                       forces - (push - external_stiffness * (q - before));
      EXPECT_LT(residual.norm(), 1e-8 * push.norm()) << "step " << i;
    }
  }
}

// Why the external stiffness exists: a stiff external spring (ω Δt = 5) held over each step, as
// step(f̃(q_n)) holds it, makes the implicit scheme's motion grow without bound; given as a
// stiffness, the same spring is stable: the trapezoidal rule keeps its energy, so the motion
// stays within its start.
TEST(ReducedIntegrator, ExternalStiffnessKeepsAStiffExternalSpringStable) {
  const double spring = 2.5e7;  // on unit modal mass: ω = 5000 rad/s, Δt = 1 ms
  const Eigen::Matrix3d stiffness = spring * Eigen::Matrix3d::Identity();
  const auto largest_late_displacement = [&](bool implicit) {
    SpringChainForces chain{3, 100.0, 1e4};
    auto integrator = make_reduced_newmark(chain, Eigen::MatrixXd::Identity(3, 3),
                                           test::trapezoidal_options(1e-3, 3, 1e-12, 0.5));
    integrator->set_state(Eigen::Vector3d(1e-3, 0.0, -1e-3), Eigen::Vector3d::Zero(),
                          Eigen::Vector3d::Zero());
    double largest = 0.0;
    for (int i = 0; i < 200; ++i) {
      const Eigen::VectorXd force = -stiffness * integrator->coordinates();
      const ReducedStepReport report =
          implicit ? integrator->step(force, stiffness) : integrator->step(force);
      if (report.status == ReducedStepStatus::failed) return HUGE_VAL;
      if (i >= 150) largest = std::max(largest, integrator->coordinates().norm());
    }
    return largest;
  };
  EXPECT_GT(largest_late_displacement(false), 1.0);    // from 1.4 mm: unstable
  EXPECT_LT(largest_late_displacement(true), 1.5e-3);  // started at 1.41 mm, at rest
}

// A wrong-sized or non-finite external stiffness fails the step and leaves the state as it was.
TEST(ReducedIntegrator, BadExternalStiffnessFailsTheStepAndKeepsTheState) {
  Chains chains;
  for (const std::unique_ptr<ReducedIntegrator>& integrator : both_schemes(chains)) {
    for (int i = 0; i < 5; ++i) integrator->step(push);
    const ReducedIntegratorState before = integrator->state();
    Eigen::Matrix3d not_finite = Eigen::Matrix3d::Identity();
    not_finite(2, 1) = std::nan("");
    EXPECT_EQ(integrator->step(push, not_finite).status, ReducedStepStatus::failed);
#ifdef NDEBUG  // a wrong size also asserts in debug builds
    EXPECT_EQ(integrator->step(push, Eigen::Matrix2d::Identity()).status,
              ReducedStepStatus::failed);
#endif
    EXPECT_EQ(integrator->coordinates(), before.coordinates);
    EXPECT_EQ(integrator->velocity(), before.velocity);
    EXPECT_EQ(integrator->state().steps, before.steps);
  }
}

TEST(ReducedIntegrator, SettersRejectBadStatesNamingTheClassAndKeepTheOldOne) {
  Chains chains;
  for (const std::unique_ptr<ReducedIntegrator>& integrator : both_schemes(chains)) {
    integrator->step(push);
    const ReducedIntegratorState before = integrator->state();
    ReducedIntegratorState wrong = before;
    wrong.velocity = Eigen::VectorXd::Zero(2);
    EXPECT_TRUE(throws_with_message<Error>([&] { integrator->set_state(wrong); },
                                           "set_state: expected vectors of 3 entries, got 2"));
    wrong = before;
    wrong.steps = -1;
    EXPECT_TRUE(throws_with_message<Error>([&] { integrator->set_state(wrong); },
                                           "set_state: negative step count -1"));
    EXPECT_TRUE(throws_with_message<Error>(
        [&] { integrator->set_mass(Eigen::MatrixXd::Zero(3, 3)); }, "not positive definite"));
    EXPECT_EQ(integrator->coordinates(), before.coordinates);
    EXPECT_EQ(integrator->velocity(), before.velocity);
    EXPECT_EQ(integrator->time(), before.steps * integrator->time_step());
  }
}

}  // namespace
}  // namespace khz::reduced
