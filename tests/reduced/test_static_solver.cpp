#include <khz/reduced/errors.hpp>
#include <khz/reduced/meshing/box_mesh.hpp>
#include <khz/reduced/solvers/fixed_dofs.hpp>
#include <khz/reduced/solvers/static_solver.hpp>
#include <khz/test/cantilever.hpp>
#include <khz/test/fixtures.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace khz::reduced {
namespace {

// Steel-like, with ν = 0 so the 3-D beam has no Poisson stiffening against Euler–Bernoulli.
const Material steel = Material::stvk(200e9, 0.0, 7800.0);

/// Relative error of the tip deflection under a small tip load against P L³ / (3 E I).
double euler_bernoulli_error(int across) {
  const test::Cantilever beam(1.0, 0.1, across, steel);
  const double load = 1e3;  // N: deflection ~ 2e-4 m, deep in the linear range
  const StaticSolution solution =
      solve_static(beam.model, beam.clamped, beam.tip_load(Eigen::Vector3d(0, 0, -load)));
  const double inertia = std::pow(beam.side, 4) / 12.0;
  const double expected = load * std::pow(beam.length, 3) / (3.0 * 200e9 * inertia);
  return std::abs(-beam.tip_displacement(solution.displacement).z() - expected) / expected;
}

TEST(StaticSolver, CantileverConvergesToEulerBernoulli) {
  // L/h = 10. Trilinear hexahedra are too stiff in bending (parasitic shear); the error falls
  // with refinement. Measured: 2 cells across 10.7 %, 4 → 2.5 %, 6 → 0.79 % (8 → 0.19 %).
  const double coarse = euler_bernoulli_error(2);
  const double medium = euler_bernoulli_error(4);
  const double fine = euler_bernoulli_error(6);
  EXPECT_LT(medium, coarse);
  EXPECT_LT(fine, medium);
  EXPECT_LT(fine, 0.01);  // the issue asks for 3 %
}

TEST(StaticSolver, LargeLoadNeedsAndUsesLoadSteps) {
  const test::Cantilever beam(1.0, 0.1, 2, steel);
  // A tip load deflecting the beam by a third of its length: geometric nonlinearity matters.
  const Eigen::VectorXd f = beam.tip_load(Eigen::Vector3d(0, 0, -2e6));
  StaticSolveOptions options;
  options.load_steps = 10;
  const StaticSolution solution = solve_static(beam.model, beam.clamped, f, options);
  Eigen::VectorXd forces;
  beam.model.internal_forces(solution.displacement, forces);
  const FixedDofs fixed(beam.model.mesh().num_vertices(), beam.clamped);
  EXPECT_LE((fixed.restrict_vector(forces - f)).norm(), 1e-8 * f.norm());
  EXPECT_LT(beam.tip_displacement(solution.displacement).z(), -0.1);
  // Clamped vertices stay put.
  for (int v : beam.clamped) EXPECT_EQ(solution.displacement.segment<3>(3 * v).norm(), 0.0);
}

// A slender rubber beam bent by 6.5 % of its length: the first Newton step raises ‖R − f‖ from
// 0.33 N to 126 N while lowering the potential energy. A line search on the residual alone cut
// step after step and failed after 50 iterations; with the energy criterion Newton converges
// as fast as without a line search (5 iterations measured).
TEST(StaticSolver, LineSearchDoesNotStallInBending) {
  const FemModel model(box_hex_mesh(Eigen::Vector3d::Zero(), {1.0, 0.1, 0.08}, {20, 2, 2}),
                       {Material::stvk(1e6, 0.3, 1100.0)});
  const Eigen::AlignedBox3d clamp(Eigen::Vector3d(-1e-9, -1, -1), Eigen::Vector3d(1e-9, 1, 1));
  const Eigen::AlignedBox3d tip(Eigen::Vector3d(1 - 1e-9, -1, -1), Eigen::Vector3d(2, 1, 1));
  const std::vector<int> tip_vertices = vertices_in_box(model.mesh().vertices, tip);
  Eigen::VectorXd f = Eigen::VectorXd::Zero(model.num_dofs());
  for (int v : tip_vertices) f(3 * v + 2) = -1.0 / static_cast<double>(tip_vertices.size());
  const StaticSolution solution =
      solve_static(model, vertices_in_box(model.mesh().vertices, clamp), f);
  EXPECT_LE(solution.iterations, 8);
  EXPECT_LT(solution.displacement(3 * tip_vertices[0] + 2), -0.05);
}

TEST(StaticSolver, ReportsEachLoadStepAndCancels) {
  const test::Cantilever beam(1.0, 0.1, 2, steel);
  const Eigen::VectorXd f = beam.tip_load(Eigen::Vector3d(0, 0, -1e3));
  StaticSolveOptions options;
  options.load_steps = 3;
  std::vector<std::int64_t> done;
  options.progress = [&](const Progress& progress) {
    EXPECT_EQ(progress.stage, "static solve");
    EXPECT_EQ(progress.total, 3);
    done.push_back(progress.done);
    return true;
  };
  (void)solve_static(beam.model, beam.clamped, f, options);
  ASSERT_GE(done.size(), 4u);
  EXPECT_EQ(done.front(), 0);
  EXPECT_EQ(done.back(), 3);
  EXPECT_TRUE(std::is_sorted(done.begin(), done.end()));

  int reports = 0;
  options.progress = [&](const Progress&) { return ++reports < 2; };
  EXPECT_TRUE(test::throws_with_message<Cancelled>(
      [&] { (void)solve_static(beam.model, beam.clamped, f, options); },
      "cancelled during static solve"));
  EXPECT_EQ(reports, 2);
}

TEST(StaticSolver, ReportsNonConvergenceWithLoadStepAndResidual) {
  const test::Cantilever beam(1.0, 0.1, 2, steel);
  StaticSolveOptions options;
  options.max_iterations = 2;
  EXPECT_TRUE(test::throws_with_message<SolverError>(
      [&] {
        solve_static(beam.model, beam.clamped, beam.tip_load(Eigen::Vector3d(0, 0, -2e6)), options);
      },
      "solve_static: no convergence at load step 1/1, Newton iteration 2"));
}

TEST(StaticSolver, UnconstrainedModelIsSingular) {
  const test::Cantilever beam(1.0, 0.1, 2, steel);
  EXPECT_TRUE(test::throws_with_message<SolverError>(
      [&] { solve_static(beam.model, {}, beam.tip_load(Eigen::Vector3d(0, 0, -1))); },
      "are the rigid motions fixed?"));
}

TEST(StaticSolver, RejectsBadInput) {
  const test::Cantilever beam(1.0, 0.1, 2, steel);
  StaticSolveOptions options;
  options.load_steps = 0;
  EXPECT_THROW(solve_static(beam.model, beam.clamped, beam.tip_load({0, 0, 1}), options), Error);
  EXPECT_THROW(solve_static(beam.model, beam.clamped, Eigen::VectorXd::Zero(3)), Error);
}

}  // namespace
}  // namespace khz::reduced
