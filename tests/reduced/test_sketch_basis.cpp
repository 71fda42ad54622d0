#include <khz/reduced/basis/sketch_basis.hpp>
#include <khz/reduced/errors.hpp>
#include <khz/reduced/solvers/static_solver.hpp>
#include <khz/test/cantilever.hpp>
#include <khz/test/fixtures.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <span>
#include <string>
#include <vector>

namespace khz::reduced {
namespace {

const Material steel = Material::stvk(200e9, 0.3, 7800.0);

/// A 0.4 m × 0.1 m × 0.1 m steel cantilever of 4 hexahedra (20 vertices), clamped at x = 0:
/// coarse, because every static solve assembles K(u) several times and Debug builds are slow.
/// Its tip compliance is about 8.4e-9 m/N; 6 MN bends it by ~5 cm, 12 % of its length.
test::Cantilever small_beam() { return test::Cantilever(0.4, 0.1, 1, steel); }

/// Total force `total` (N) spread evenly over the tip vertices.
ForceLoad tip_load(const test::Cantilever& beam, const Eigen::Vector3d& total) {
  ForceLoad load;
  for (int v : beam.tip) {
    load.forces.push_back({v, total / static_cast<double>(beam.tip.size())});
  }
  return load;
}

const Eigen::Vector3d down(0, 0, -1);
const Eigen::Vector3d side(0, 1, 0);

/// The recorded sketch: tip loads down (−z) at two magnitudes and sideways (+y), a near
/// duplicate the force thinning must drop, and a load that differs from another only by a push
/// on a clamped vertex: far in force, identical in deformation. A tip load of total F has norm
/// F/2 here (4 tip vertices), so distinct loads are ≥ 1 MN apart.
std::vector<ForceLoad> sketched_loads(const test::Cantilever& beam) {
  std::vector<ForceLoad> loads = {
      tip_load(beam, 2e6 * down),               // 0
      tip_load(beam, 6e6 * down),               // 1
      tip_load(beam, 2e6 * (1 + 1e-4) * down),  // 2: 100 N from load 0
      tip_load(beam, 6e6 * side),               // 3
      tip_load(beam, 6e6 * side),               // 4: load 3 plus a push on the clamp, below
  };
  loads[4].forces.push_back({beam.clamped.front(), Eigen::Vector3d(1e6, 0, 0)});
  return loads;
}

SketchBasisOptions sketch_options(int basis_size) {
  SketchBasisOptions options;
  options.force_separation = 1e3;         // N
  options.deformation_separation = 1e-4;  // m·√kg: distinct deformations here are ≥ 0.05 apart
  options.basis_size = basis_size;
  // Plain Newton converges quadratically on these loads: 4–5 iterations up to 6 MN, where the
  // residual-norm line search needs 9–22 (it cuts the steps that stretch the beam axially).
  options.static_solve.line_search = false;
  return options;
}

Eigen::VectorXd static_deformation(const test::Cantilever& beam, const ForceLoad& load) {
  return solve_static(beam.model, beam.clamped, load.to_vector(beam.model.mesh().num_vertices()),
                      sketch_options(1).static_solve)
      .displacement;
}

/// Mass-norm error of projecting u onto span(U) for mass-orthonormal U, relative to ‖u‖_M.
double relative_projection_error(const Eigen::MatrixXd& basis, const SparseMatrix& mass,
                                 const Eigen::VectorXd& u) {
  const Eigen::VectorXd mu = mass * u;
  const Eigen::VectorXd residual = u - basis * (basis.transpose() * mu);
  return std::sqrt(residual.dot(mass * residual)) / std::sqrt(u.dot(mu));
}

TEST(SketchBasis, ThinsLoadsAndDeformationsAndSpansTheSketchedRange) {
  const test::Cantilever beam = small_beam();
  const std::vector<ForceLoad> loads = sketched_loads(beam);
  SketchBasisOptions options = sketch_options(3);
  std::vector<std::string> stages;
  int solves_reported = 0;
  options.progress = [&](const Progress& progress) {
    if (stages.empty() || stages.back() != progress.stage) stages.emplace_back(progress.stage);
    if (progress.stage == "static solves") solves_reported = static_cast<int>(progress.done);
    return true;
  };
  SketchReport report;
  const Basis basis = sketch_basis(beam.model, beam.clamped, loads, options, report);

  EXPECT_EQ(stages, (std::vector<std::string>{"force selection", "static solves", "mass distances",
                                              "deformation selection", "mass PCA"}));
  EXPECT_EQ(report.num_loads, 5);
  // Of the near-duplicate pair the lower index stays (equal densities).
  EXPECT_EQ(report.selected_loads, (std::vector<int>{0, 1, 3, 4}));
  EXPECT_EQ(solves_reported, 4);
  EXPECT_TRUE(report.failures.empty());
  ASSERT_EQ(report.static_iterations.size(), 4u);
  for (int iterations : report.static_iterations) EXPECT_GE(iterations, 2);
  // Loads 3 and 4 bend the beam identically: the mass-distance thinning keeps one.
  EXPECT_EQ(report.kept_loads, (std::vector<int>{0, 1, 3}));
  ASSERT_EQ(report.deformations.cols(), 3);
  EXPECT_EQ(report.singular_values.size(), 3);
  EXPECT_EQ(basis.recipe, "sketch: 5 loads, 4 selected, 3 deformations kept, mass PCA to r=3");
  EXPECT_EQ(basis.fixed_vertices, beam.clamped);
  ASSERT_EQ(basis.size(), 3);
  ASSERT_EQ(basis.vectors.rows(), beam.model.num_dofs());

  const SparseMatrix mass = beam.model.mass_matrix();
  const Eigen::MatrixXd gram = basis.vectors.transpose() * (mass * basis.vectors);
  EXPECT_LT((gram - Eigen::MatrixXd::Identity(3, 3)).cwiseAbs().maxCoeff(), 1e-10);
  for (int v : beam.clamped) {
    EXPECT_EQ(basis.vectors.middleRows(3 * v, 3).cwiseAbs().maxCoeff(), 0.0) << "vertex " << v;
  }

  // With r = the number of kept deformations each is in span(U) up to round-off (measured
  // ≤ 5e-16).
  for (Eigen::Index k = 0; k < 3; ++k) {
    EXPECT_LT(relative_projection_error(basis.vectors, mass, report.deformations.col(k)), 1e-12)
        << "kept deformation " << k;
  }

  // A new load inside the sketched range: 4 MN down, between the sketched 2 and 6 MN. Its
  // deformation is not a multiple of either (geometric nonlinearity: the tip also moves back
  // and the section rotates), but the two sketched shapes span the linear shape plus the
  // leading nonlinear correction, so only the higher-order part is lost.
  const Eigen::VectorXd between = static_deformation(beam, tip_load(beam, 4e6 * down));
  const double sketch_error = relative_projection_error(basis.vectors, mass, between);
  // For comparison, a basis of only the 2 MN shape (what a linear model would offer).
  const Eigen::VectorXd shape = report.deformations.col(0);
  const Eigen::MatrixXd linear_basis = shape / std::sqrt(shape.dot(mass * shape));
  const double linear_error = relative_projection_error(linear_basis, mass, between);
  // Measured: 1.29e-4 in the sketch basis, 2.27e-2 on the 2 MN shape alone.
  EXPECT_LT(sketch_error, 3e-4);
  EXPECT_LT(sketch_error, 0.02 * linear_error);
}

TEST(SketchBasis, CancelledBetweenStaticSolves) {
  const test::Cantilever beam = small_beam();
  const std::vector<ForceLoad> loads = sketched_loads(beam);
  SketchBasisOptions options = sketch_options(3);
  int last_done = -1;
  options.progress = [&](const Progress& progress) {
    if (progress.stage == "static solves") last_done = static_cast<int>(progress.done);
    return !(progress.stage == "static solves" && progress.done == 1);
  };
  SketchReport report;
  report.num_loads = -5;
  EXPECT_TRUE(test::throws_with_message<Cancelled>(
      [&] { sketch_basis(beam.model, beam.clamped, loads, options, report); },
      "cancelled during static solves"));
  EXPECT_EQ(last_done, 1);          // stopped right after the first solve
  EXPECT_EQ(report.num_loads, -5);  // the report is left alone
}

TEST(SketchBasis, CancelledWithinAStaticSolve) {
  const test::Cantilever beam = small_beam();
  const std::vector<ForceLoad> loads = sketched_loads(beam);
  SketchBasisOptions options = sketch_options(3);
  int solve_reports = 0;
  options.progress = [&](const Progress& progress) {
    if (progress.stage != "static solves") return true;
    EXPECT_EQ(progress.done, 0);  // still inside the first solve
    return ++solve_reports < 2;   // the stage's start, then the first Newton iteration
  };
  EXPECT_TRUE(test::throws_with_message<Cancelled>(
      [&] { (void)sketch_basis(beam.model, beam.clamped, loads, options); },
      "cancelled during static solves"));
  EXPECT_EQ(solve_reports, 2);
}

TEST(SketchBasis, FailedStaticSolveStopsOrIsSkippedAndReported) {
  const test::Cantilever beam = small_beam();
  // With at most 3 Newton iterations in one load step, the small loads converge (3 iterations
  // were measured for 0.1 MN) and the 20 MN one does not (it needs 6).
  const std::vector<ForceLoad> loads = {tip_load(beam, 1e5 * down), tip_load(beam, 2e7 * down),
                                        tip_load(beam, 1e5 * side)};
  SketchBasisOptions options = sketch_options(2);
  options.static_solve.max_iterations = 3;
  EXPECT_TRUE(test::throws_with_message<SolverError>(
      [&] { sketch_basis(beam.model, beam.clamped, loads, options); },
      "sketch_basis: the static solve of load 1 failed: solve_static: no convergence"));

  options.skip_failed_solves = true;
  SketchReport report;
  const Basis basis = sketch_basis(beam.model, beam.clamped, loads, options, report);
  ASSERT_EQ(report.failures.size(), 1u);
  EXPECT_EQ(report.failures[0].load, 1);
  EXPECT_NE(report.failures[0].message.find("solve_static: no convergence"), std::string::npos);
  EXPECT_EQ(report.selected_loads, (std::vector<int>{0, 1, 2}));
  ASSERT_EQ(report.static_iterations.size(), 3u);
  EXPECT_EQ(report.static_iterations[1], -1);
  EXPECT_EQ(report.kept_loads, (std::vector<int>{0, 2}));
  EXPECT_EQ(basis.recipe,
            "sketch: 3 loads, 3 selected, 1 failed to solve, 2 deformations kept, mass PCA to r=2");
  EXPECT_EQ(basis.size(), 2);

  // Nothing left to build a basis from.
  const std::vector<ForceLoad> hopeless = {tip_load(beam, 2e7 * down)};
  EXPECT_TRUE(test::throws_with_message<SolverError>(
      [&] { sketch_basis(beam.model, beam.clamped, hopeless, options); },
      "sketch_basis: all 1 static solves failed; the first (load 0): solve_static:"));
}

TEST(SketchBasis, RejectsBadInput) {
  const test::Cantilever beam = small_beam();
  const std::vector<ForceLoad> loads = {tip_load(beam, 1e5 * down), tip_load(beam, 1e5 * side)};
  const auto fails = [&](std::span<const ForceLoad> given, const SketchBasisOptions& options,
                         const char* message) {
    return test::throws_with_message<Error>(
        [&] { sketch_basis(beam.model, beam.clamped, given, options); }, message);
  };
  EXPECT_TRUE(fails({}, sketch_options(1), "sketch_basis: no loads given"));
  EXPECT_TRUE(
      fails(loads, sketch_options(0), "SketchBasisOptions: basis_size must be at least 1, got 0"));
  SketchBasisOptions negative = sketch_options(1);
  negative.deformation_separation = -1.0;
  EXPECT_TRUE(fails(loads, negative,
                    "SketchBasisOptions: deformation_separation must be finite and non-negative, "
                    "got -1"));
  SketchBasisOptions no_steps = sketch_options(1);
  no_steps.static_solve.load_steps = 0;
  EXPECT_TRUE(fails(loads, no_steps, "SketchBasisOptions: static_solve needs load_steps"));
  const std::vector<ForceLoad> outside = {loads[0], ForceLoad{{PointForce{20, {0, 0, 1}}}}};
  EXPECT_TRUE(fails(outside, sketch_options(1),
                    "sketch_basis: load 1: point force 0 acts on vertex 20, but the mesh has 20 "
                    "vertices"));
  const std::vector<int> bad_anchor = {0, 20};
  EXPECT_TRUE(test::throws_with_message<Error>(
      [&] { sketch_basis(beam.model, bad_anchor, loads, sketch_options(1)); },
      "sketch_basis: fixed vertex 20 is outside [0, 20)"));
  // Two deformations cannot give three basis vectors.
  EXPECT_TRUE(fails(loads, sketch_options(3),
                    "sketch_basis: basis_size 3 exceeds the 2 deformations kept of 2 solved"));
}

}  // namespace
}  // namespace khz::reduced
