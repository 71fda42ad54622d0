#include <khz/reduced/basis/sample_selection.hpp>
#include <khz/reduced/basis/sketch_basis.hpp>
#include <khz/reduced/errors.hpp>

#include <khz/reduced/stage_progress.hpp>
#include "basis/generator_support.hpp"
#include "detail/number_text.hpp"

#include <cmath>
#include <cstdint>
#include <string>
#include <utility>

namespace khz::reduced {
namespace {

constexpr std::string_view who = "sketch_basis";

void check_length(double value, const char* name) {
  if (!std::isfinite(value) || value < 0.0) {
    throw Error(std::string("SketchBasisOptions: ") + name +
                " must be finite and non-negative, got " + detail::number_text(value));
  }
}

/// Columns `columns` of `samples`.
Eigen::MatrixXd gather_columns(const Eigen::MatrixXd& samples, const std::vector<int>& columns) {
  Eigen::MatrixXd gathered(samples.rows(), static_cast<Eigen::Index>(columns.size()));
  for (std::size_t c = 0; c < columns.size(); ++c) {
    gathered.col(static_cast<Eigen::Index>(c)) = samples.col(columns[c]);
  }
  return gathered;
}

}  // namespace

void SketchBasisOptions::validate() const {
  check_length(force_separation, "force_separation");
  check_length(force_kernel_width, "force_kernel_width");
  check_length(deformation_separation, "deformation_separation");
  check_length(deformation_kernel_width, "deformation_kernel_width");
  if (basis_size < 1) {
    throw Error("SketchBasisOptions: basis_size must be at least 1, got " +
                std::to_string(basis_size));
  }
  if (!(rank_tolerance >= 0.0 && rank_tolerance < 1.0)) {
    throw Error("SketchBasisOptions: rank_tolerance must lie in [0, 1), got " +
                detail::number_text(rank_tolerance));
  }
  // Checked here too so that a bad setting fails before the first expensive solve.
  if (static_solve.load_steps < 1 || static_solve.max_iterations < 1 ||
      !(static_solve.tolerance > 0)) {
    throw Error(
        "SketchBasisOptions: static_solve needs load_steps and max_iterations of at least 1 and "
        "a positive tolerance");
  }
}

Basis sketch_basis(const FemModel& model, std::span<const int> fixed_vertices,
                   std::span<const ForceLoad> loads, const SketchBasisOptions& options) {
  SketchReport report;
  return sketch_basis(model, fixed_vertices, loads, options, report);
}

// Thesis §2.8.2, "Sketch-based basis generation": the recorded forces are thinned to a
// separation distance, solved by a full offline static solver, the deformations thinned to a
// mass separation, and mass-PCA (§2.8.1) extracts the basis.
Basis sketch_basis(const FemModel& model, std::span<const int> fixed_vertices,
                   std::span<const ForceLoad> loads, const SketchBasisOptions& options,
                   SketchReport& report_out) {
  options.validate();
  if (loads.empty()) throw Error("sketch_basis: no loads given");
  const Eigen::Index num_vertices = model.mesh().num_vertices();
  for (std::size_t l = 0; l < loads.size(); ++l) {
    try {
      loads[l].validate(num_vertices);
    } catch (const Error& error) {
      throw Error("sketch_basis: load " + std::to_string(l) + ": " + error.what());
    }
  }
  const std::vector<int> fixed = detail::sorted_fixed_vertices(fixed_vertices, num_vertices, who);
  const ProgressCallback& progress = options.progress;
  SketchReport report;
  report.num_loads = static_cast<int>(loads.size());

  // 1. Loads thinned to δ_f in the Euclidean norm of the force vectors, densest first.
  StageProgress force_stage(progress, "force selection", 1);
  report.selected_loads =
      select_separated_samples(force_distances(loads),
                               {options.force_separation, options.force_kernel_width})
          .kept;
  force_stage.finish();

  // 2. One full nonlinear static solve R(u) = f per retained load (thesis §2.1.10).
  const auto num_selected = static_cast<std::int64_t>(report.selected_loads.size());
  StageProgress solve_stage(progress, "static solves", num_selected);
  Eigen::MatrixXd solutions(model.num_dofs(), static_cast<Eigen::Index>(num_selected));
  std::vector<int> solved_loads;
  // Each Newton iteration of a solve re-asks the caller (same `done`), so cancelling does not
  // wait for the running solve to finish.
  StaticSolveOptions static_options = options.static_solve;
  static_options.progress = [&](const Progress&) {
    solve_stage.advance(0);
    return true;
  };
  for (std::int64_t s = 0; s < num_selected; ++s) {
    const int load = report.selected_loads[static_cast<std::size_t>(s)];
    try {
      const StaticSolution solution =
          solve_static(model, fixed, loads[static_cast<std::size_t>(load)].to_vector(num_vertices),
                       static_options);
      solutions.col(static_cast<Eigen::Index>(solved_loads.size())) = solution.displacement;
      solved_loads.push_back(load);
      report.static_iterations.push_back(solution.iterations);
    } catch (const SolverError& error) {
      if (!options.skip_failed_solves) {
        throw SolverError("sketch_basis: the static solve of load " + std::to_string(load) +
                          " failed: " + error.what());
      }
      report.failures.push_back({load, error.what()});
      report.static_iterations.push_back(-1);
    }
    solve_stage.advance();
  }
  if (solved_loads.empty()) {
    throw SolverError("sketch_basis: all " + std::to_string(num_selected) +
                      " static solves failed; the first (load " +
                      std::to_string(report.failures.front().load) +
                      "): " + report.failures.front().message);
  }
  solutions.conservativeResize(Eigen::NoChange, static_cast<Eigen::Index>(solved_loads.size()));

  // 3. Deformations thinned to δ_u in the mass norm (eq. 2.40).
  const SparseMatrix mass = model.mass_matrix(MassLumping::consistent);
  const Eigen::MatrixXd distances =
      options.metric == PcaMetric::lumped_mass
          ? mass_distances(solutions, model.mass_matrix(MassLumping::lumped), progress)
          : mass_distances(solutions, mass, progress);
  StageProgress deformation_stage(progress, "deformation selection", 1);
  const std::vector<int> kept_columns =
      select_separated_samples(distances,
                               {options.deformation_separation, options.deformation_kernel_width})
          .kept;
  deformation_stage.finish();
  for (int column : kept_columns) {
    report.kept_loads.push_back(solved_loads[static_cast<std::size_t>(column)]);
  }
  report.deformations = gather_columns(solutions, kept_columns);
  solutions.resize(0, 0);
  const auto num_kept = static_cast<int>(kept_columns.size());
  if (options.basis_size > num_kept) {
    throw Error("sketch_basis: basis_size " + std::to_string(options.basis_size) + " exceeds the " +
                std::to_string(num_kept) + " deformations kept of " +
                std::to_string(solved_loads.size()) +
                " solved; sketch more loads or lower the separations");
  }

  // 4. Mass-PCA to r vectors (§2.8.1).
  PcaOptions pca_options;
  pca_options.basis_size = options.basis_size;
  pca_options.metric = options.metric;
  pca_options.rank_tolerance = options.rank_tolerance;
  pca_options.progress = progress;
  PcaResult pca = principal_components(report.deformations, mass, pca_options);

  Basis basis;
  basis.vectors = std::move(pca.basis);
  detail::zero_fixed_rows(basis.vectors, fixed);
  basis.fixed_vertices = fixed;
  basis.recipe =
      "sketch: " + std::to_string(loads.size()) + " loads, " + std::to_string(num_selected) +
      " selected, " +
      (report.failures.empty() ? std::string()
                               : std::to_string(report.failures.size()) + " failed to solve, ") +
      std::to_string(num_kept) + " deformations kept, " + detail::pca_name(options.metric) +
      " to r=" + std::to_string(options.basis_size);
  report.singular_values = std::move(pca.singular_values);
  report_out = std::move(report);
  return basis;
}

}  // namespace khz::reduced
