#include <khz/reduced/basis/simulation_data_basis.hpp>
#include <khz/reduced/errors.hpp>
#include <khz/reduced/solvers/full_newmark.hpp>
#include <khz/test/cantilever.hpp>
#include <khz/test/fixtures.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

namespace khz::reduced {
namespace {

const Material steel = Material::stvk(200e9, 0.3, 7800.0);

/// A 0.4 m steel cantilever of 4 hexahedra (coarse: Debug builds assemble K slowly); its first
/// bending period is about 1.5 ms.
test::Cantilever small_beam() { return test::Cantilever(0.4, 0.1, 1, steel); }

/// Displacements of a short full simulation, one column per step: a 1 MN downward tip push
/// held for 0.5 ms, then released and left to swing, Δt = 0.1 ms, 20 steps.
Eigen::MatrixXd simulate(const test::Cantilever& beam) {
  FullNewmarkOptions options;
  options.newmark.time_step = 1e-4;
  FullNewmark integrator(beam.model, beam.clamped, options);
  const Eigen::VectorXd push = beam.tip_load(Eigen::Vector3d(0, 0, -1e6));
  const Eigen::VectorXd none = Eigen::VectorXd::Zero(beam.model.num_dofs());
  constexpr int steps = 20;
  Eigen::MatrixXd snapshots(beam.model.num_dofs(), steps);
  for (int step = 0; step < steps; ++step) {
    const StepReport report = integrator.step(step < 5 ? push : none);
    EXPECT_TRUE(report.converged) << "step " << step;
    snapshots.col(step) = integrator.displacement();
  }
  return snapshots;
}

/// Four snapshots a + s·b (s = 0…3), zero at the clamp: they span two directions.
Eigen::MatrixXd synthetic_snapshots(const test::Cantilever& beam) {
  Eigen::MatrixXd snapshots(beam.model.num_dofs(), 4);
  for (Eigen::Index s = 0; s < 4; ++s) {
    snapshots.col(s) = 1e-3 * beam.tip_load(Eigen::Vector3d(0, 0.1 * static_cast<double>(s), 1));
  }
  return snapshots;
}

double relative_projection_error(const Eigen::MatrixXd& basis, const SparseMatrix& mass,
                                 const Eigen::VectorXd& u) {
  const Eigen::VectorXd mu = mass * u;
  const Eigen::VectorXd residual = u - basis * (basis.transpose() * mu);
  return std::sqrt(residual.dot(mass * residual)) / std::sqrt(u.dot(mu));
}

TEST(SimulationDataBasis, ReproducesTheSnapshots) {
  const test::Cantilever beam = small_beam();
  const Eigen::MatrixXd snapshots = simulate(beam);
  const SparseMatrix mass = beam.model.mass_matrix();
  PcaOptions all;
  all.basis_size = 1;
  const Eigen::VectorXd sigma = principal_components(snapshots, mass, all).singular_values;
  ASSERT_EQ(sigma.size(), 20);
  // Worst relative mass-norm error of a snapshot, measured: r = 3 8.6e-2, r = 6 1.9e-3, and
  // r = 20 (all of them) 3.4e-12, round-off amplified by σ₂₀/σ₁ = 1.6e-8.
  const double bounds[] = {0.2, 5e-3, 1e-10};
  int which = 0;
  for (int r : {3, 6, 20}) {
    SCOPED_TRACE(r);
    const Basis basis = simulation_data_basis(beam.model, beam.clamped, snapshots, r);
    EXPECT_EQ(basis.recipe, "simulation data: 20 snapshots, mass PCA to r=" + std::to_string(r));
    EXPECT_EQ(basis.fixed_vertices, beam.clamped);
    ASSERT_EQ(basis.size(), r);
    const Eigen::MatrixXd gram = basis.vectors.transpose() * (mass * basis.vectors);
    EXPECT_LT((gram - Eigen::MatrixXd::Identity(r, r)).cwiseAbs().maxCoeff(), 1e-10);
    for (int v : beam.clamped) EXPECT_EQ(basis.vectors.middleRows(3 * v, 3).norm(), 0.0);
    double worst = 0.0;
    double total_squared = 0.0;
    for (Eigen::Index s = 0; s < snapshots.cols(); ++s) {
      const Eigen::VectorXd u = snapshots.col(s);
      worst = std::max(worst, relative_projection_error(basis.vectors, mass, u));
      const Eigen::VectorXd residual = u - basis.vectors * (basis.vectors.transpose() * (mass * u));
      total_squared += residual.dot(mass * residual);
    }
    EXPECT_LT(worst, bounds[which++]);
    // Mass-PCA is optimal: the squared errors add up to the discarded σᵢ² (§2.8.1).
    if (r < 20) {
      EXPECT_NEAR(total_squared, sigma.tail(20 - r).squaredNorm(),
                  1e-6 * sigma.tail(20 - r).squaredNorm());
    }
  }
}

TEST(SimulationDataBasis, ReportsProgressAndCanBeCancelled) {
  const test::Cantilever beam = small_beam();
  const Eigen::MatrixXd snapshots = synthetic_snapshots(beam);
  SimulationDataBasisOptions options;
  bool saw_pca = false;
  options.progress = [&](const Progress& progress) {
    saw_pca = saw_pca || progress.stage == "mass PCA";
    return true;
  };
  simulation_data_basis(beam.model, beam.clamped, snapshots, 2, options);
  EXPECT_TRUE(saw_pca);
  options.progress = [](const Progress&) { return false; };
  EXPECT_TRUE(test::throws_with_message<Cancelled>(
      [&] { simulation_data_basis(beam.model, beam.clamped, snapshots, 2, options); },
      "cancelled during mass PCA"));
}

TEST(SimulationDataBasis, RejectsBadSnapshots) {
  const test::Cantilever beam = small_beam();
  const Eigen::Index dofs = beam.model.num_dofs();
  const Eigen::MatrixXd snapshots = synthetic_snapshots(beam);
  const auto fails = [&](const Eigen::MatrixXd& given, int r, const char* message,
                         const SimulationDataBasisOptions& options = {}) {
    return test::throws_with_message<Error>(
        [&] { simulation_data_basis(beam.model, beam.clamped, given, r, options); }, message);
  };
  EXPECT_TRUE(
      fails(Eigen::MatrixXd::Zero(dofs - 3, 4), 1,
            "simulation_data_basis: the snapshots have 57 rows, but the model has 60 dofs"));
  EXPECT_TRUE(fails(Eigen::MatrixXd(dofs, 0), 1, "simulation_data_basis: no snapshots given"));
  EXPECT_TRUE(fails(snapshots, 0, "simulation_data_basis: basis_size 0 is outside [1, 4]"));
  EXPECT_TRUE(fails(snapshots, 5, "simulation_data_basis: basis_size 5 is outside [1, 4]"));

  Eigen::MatrixXd nan = snapshots;
  nan(3 * 12 + 1, 2) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_TRUE(
      fails(nan, 2, "simulation_data_basis: snapshot 2 is not finite at vertex 12 (dof 37)"));

  const int anchor = beam.clamped[3];
  Eigen::MatrixXd moved = snapshots;
  moved(3 * anchor + 2, 3) = 1e-6;
  const std::string message = "simulation_data_basis: snapshot 3 moves fixed vertex " +
                              std::to_string(anchor) + " by 1e-06 m";
  EXPECT_TRUE(fails(moved, 2, message.c_str()));
  // Within a looser tolerance the same data is accepted, and the basis is zero there anyway.
  SimulationDataBasisOptions loose;
  loose.fixed_tolerance = 1e-2;
  const Basis basis = simulation_data_basis(beam.model, beam.clamped, moved, 2, loose);
  EXPECT_EQ(basis.vectors.middleRows(3 * anchor, 3).norm(), 0.0);

  SimulationDataBasisOptions negative;
  negative.fixed_tolerance = -1.0;
  EXPECT_TRUE(fails(snapshots, 2,
                    "simulation_data_basis: fixed_tolerance must be finite and non-negative",
                    negative));
  const std::vector<int> bad_anchor = {-1};
  EXPECT_TRUE(test::throws_with_message<Error>(
      [&] { simulation_data_basis(beam.model, bad_anchor, snapshots, 1); },
      "simulation_data_basis: fixed vertex -1 is outside [0, 20)"));
  // The four snapshots span two directions.
  EXPECT_TRUE(fails(snapshots, 3, "principal_components: the samples span only 2 directions"));
}

}  // namespace
}  // namespace khz::reduced
