#include "product_builders.hpp"

#include <khz/reduced/basis/force_load.hpp>
#include <khz/reduced/basis/linear_modes.hpp>
#include <khz/reduced/basis/modal_derivative_basis.hpp>
#include <khz/reduced/basis/simulation_data_basis.hpp>
#include <khz/reduced/basis/sketch_basis.hpp>
#include <khz/reduced/solvers/full_newmark.hpp>
#include <khz/reduced/stage_progress.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace khz::scene::detail {
namespace {

reduced::Basis modes_basis(const reduced::FemModel& fem, std::span<const int> fixed_vertices,
                           const BasisDescription& basis,
                           const reduced::ProgressCallback& progress) {
  if (basis.modal_derivatives) {
    reduced::ModalDerivativeBasisOptions options = basis.modal;
    options.progress = progress;
    return reduced::modal_derivative_basis(fem, fixed_vertices, options);
  }
  reduced::LinearModesOptions options = basis.modal.modes;
  options.progress = progress;
  const reduced::LinearModes modes = reduced::compute_linear_modes(fem, fixed_vertices, options);
  reduced::Basis result;
  result.vectors = modes.modes.leftCols(basis.modal.basis_size);
  result.fixed_vertices = modes.fixed_vertices;
  result.recipe = "linear modes: the first r=" + std::to_string(basis.modal.basis_size) +
                  " of k=" + std::to_string(options.num_modes);
  return result;
}

reduced::Basis sketch(const reduced::FemModel& fem, std::span<const int> fixed_vertices,
                      const BasisDescription& basis, const reduced::ProgressCallback& progress,
                      std::string& note) {
  const std::vector<reduced::ForceLoad> loads =
      reduced::read_force_loads(basis.loads_path, fem.mesh().num_vertices());
  reduced::SketchBasisOptions options = basis.sketch;
  options.progress = progress;
  reduced::SketchReport report;
  reduced::Basis result = reduced::sketch_basis(fem, fixed_vertices, loads, options, report);
  if (!report.failures.empty()) {
    note = std::to_string(report.failures.size()) + " of " +
           std::to_string(report.selected_loads.size()) + " static solves failed and were skipped";
  }
  return result;
}

/// The snapshots of basis.simulation (docs/SCENES.md): from rest, each load held for hold_steps
/// steps and released for release_steps; the displacement after every snapshot_every-th step.
Eigen::MatrixXd simulation_snapshots(const reduced::FemModel& fem,
                                     std::span<const int> fixed_vertices,
                                     const BasisDescription& basis,
                                     const reduced::ProgressCallback& progress, std::string& note) {
  const SimulationRunDescription& run = basis.simulation;
  const std::vector<reduced::ForceLoad> loads =
      reduced::read_force_loads(basis.loads_path, fem.mesh().num_vertices());
  reduced::FullNewmark simulation(fem, fixed_vertices, run.integrator);

  const auto total_steps = static_cast<std::int64_t>(loads.size()) *
                           (std::int64_t{run.hold_steps} + std::int64_t{run.release_steps});
  reduced::StageProgress stage(progress, "full simulation", total_steps);
  std::vector<Eigen::VectorXd> snapshots;
  std::int64_t steps = 0;
  std::int64_t unconverged = 0;
  const auto step = [&](const Eigen::VectorXd& force) {
    if (!simulation.step(force).converged) ++unconverged;
    if (++steps % run.snapshot_every == 0) snapshots.push_back(simulation.displacement());
    stage.advance();
  };
  const Eigen::VectorXd no_force = Eigen::VectorXd::Zero(fem.num_dofs());
  for (const reduced::ForceLoad& load : loads) {
    const Eigen::VectorXd force = load.to_vector(fem.mesh().num_vertices());
    for (int i = 0; i < run.hold_steps; ++i) step(force);
    for (int i = 0; i < run.release_steps; ++i) step(no_force);
  }
  stage.finish();
  if (unconverged > 0) {
    note = std::to_string(unconverged) + " of " + std::to_string(steps) +
           " simulation steps did not converge within max_newton_iterations";
  }
  Eigen::MatrixXd matrix(fem.num_dofs(), static_cast<Eigen::Index>(snapshots.size()));
  for (std::size_t i = 0; i < snapshots.size(); ++i) {
    matrix.col(static_cast<Eigen::Index>(i)) = snapshots[i];
  }
  return matrix;
}

}  // namespace

reduced::Basis compute_basis(const reduced::FemModel& fem, std::span<const int> fixed_vertices,
                             const BasisDescription& basis,
                             const reduced::ProgressCallback& progress, std::string& note) {
  switch (basis.method) {
    case BasisMethod::modes:
      return modes_basis(fem, fixed_vertices, basis, progress);
    case BasisMethod::sketch:
      return sketch(fem, fixed_vertices, basis, progress, note);
    case BasisMethod::simulation_data:
      break;
  }
  const Eigen::MatrixXd snapshots =
      simulation_snapshots(fem, fixed_vertices, basis, progress, note);
  reduced::SimulationDataBasisOptions options = basis.simulation_data;
  options.progress = progress;
  return reduced::simulation_data_basis(fem, fixed_vertices, snapshots,
                                        basis.simulation_data_basis_size, options);
}

}  // namespace khz::scene::detail
