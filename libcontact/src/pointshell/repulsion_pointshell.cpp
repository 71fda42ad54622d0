#include <khz/contact/pointshell/repulsion_pointshell.hpp>

#include <khz/contact/field/isosurface.hpp>
#include <khz/contact/field/mesh_distance.hpp>
#include <khz/contact/pointshell/pointshell_sampling.hpp>

#include <khz/reduced/mesh/surface_area.hpp>
#include <khz/reduced/stage_progress.hpp>

#include "pointshell/repulsion_relaxation.hpp"
#include "pointshell/repulsion_seeding.hpp"
#include "pointshell/repulsion_spacing.hpp"
#include "pointshell/split_mix.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <utility>
#include <vector>

namespace khz::contact {

namespace {

// η = step_factor · R. Estimated, a hexagonal packing at R = 1.5 spacings stays stable under
// Jacobi steps up to about 0.27 R (2/λ for its stiffest mode, 6 neighbours at d/R = 0.72 with
// |g'| = 1.22). Measured on a sphere at the same tolerance: 0.3 R made some particles oscillate
// (their η halved), 0.1 R left the points less uniform (99th/1st nearest-neighbour percentile
// 1.40 against 1.34 at 0.2 R).
constexpr double step_factor = 0.2;
// The longest move in one iteration, in spacings: keeps the first iterations after random
// seeding, when two particles can start almost on top of each other, from throwing particles
// across thin parts.
constexpr double max_move_factor = 0.5;
// ε when the options leave it to us, in grid spacings: Newton converges quadratically, so a
// tight ε costs one step more.
constexpr double default_projection_tolerance = 1e-4;

}  // namespace

Pointshell repulsion_pointshell(const DistanceGrid& field, double level,
                                const TriangleMesh& surface_for_normals,
                                const RepulsionOptions& options, RepulsionReport* report) {
  options.validate();
  if (!std::isfinite(level)) throw Error("repulsion_pointshell: the level is not finite");
  const MeshDistance normal_source(surface_for_normals);
  const double grid_spacing = field.geometry().spacing;
  const double epsilon = options.projection_tolerance > 0.0
                             ? options.projection_tolerance
                             : default_projection_tolerance * grid_spacing;

  // S of §3.8.1: only needed to draw starting positions.
  TriangleMesh level_set;
  {
    reduced::StageProgress stage(options.progress, "pointshell level set", 1);
    level_set = isosurface(field, level);
    stage.finish();
  }
  if (level_set.num_triangles() == 0) {
    throw Error("repulsion_pointshell: the level set {d = " + std::to_string(level) +
                "} does not cross the grid");
  }
  const double area = reduced::surface_area(level_set);

  RepulsionReport summary;
  summary.level_set_area = area;
  summary.level_set_triangles = level_set.num_triangles();
  summary.projection_tolerance = epsilon;

  Pointshell pointshell;
  Eigen::Index total = 0;
  for (int i = 0; i < options.levels; ++i) {
    total += options.first_level_points << (2 * i);
    pointshell.level_ends.push_back(total);
  }
  pointshell.points.resize(total, 3);
  // The unit field gradient at each point: the level set's normal, for tangential moves.
  std::vector<Eigen::Vector3d> normals(static_cast<std::size_t>(total));

  for (int i = 0; i < options.levels; ++i) {
    const Eigen::Index begin = pointshell.level_begin(i);
    const Eigen::Index end = pointshell.level_end(i);
    // The spacing of N points spread evenly over A; R and η scale with it, so R halves per
    // level as in the thesis (exactly in the limit: N grows by 5, 4.2, 4.05, … ×).
    const double spacing = std::sqrt(area / static_cast<double>(end));
    detail::RelaxationSettings settings;
    settings.level = level;
    settings.spacing = spacing;
    settings.radius = options.radius_factor * spacing;
    settings.step = step_factor * settings.radius;
    settings.max_move = max_move_factor * spacing;
    settings.tolerance = options.tolerance;
    settings.max_iterations = options.max_iterations;
    settings.projection_tolerance = epsilon;
    // Room to come back from a full move off a sharp feature, and from S to the level set.
    settings.projection_max_step = std::max(2.0 * grid_spacing, settings.max_move);

    // The level's stage counts its seeding and its statistics as one unit each: on the finest
    // level of a 262k-point shell they take 0.8 and 0.15 s (bench_pointshell).
    const std::string stage_name = "particle repulsion level " + std::to_string(i);
    reduced::StageProgress stage(options.progress, stage_name, options.max_iterations + 2);
    const std::uint64_t level_seed =
        detail::split_mix(options.seed + 0x9e3779b97f4a7c15ULL * static_cast<std::uint64_t>(i));
    detail::seed_level(field, level_set, {level, epsilon, settings.projection_max_step, spacing},
                       level_seed, begin, end, pointshell.points, normals);
    stage.advance();
    const detail::RelaxationResult relaxed =
        detail::relax_level(field, pointshell.points, begin, end, normals, settings, stage);

    RepulsionLevelReport& figures = summary.levels.emplace_back();
    figures.points = end - begin;
    figures.radius = settings.radius;
    figures.spacing = spacing;
    figures.initial_step = settings.step;
    figures.final_step = relaxed.mean_step;
    figures.iterations = relaxed.iterations;
    figures.converged = relaxed.converged;
    figures.mean_movement = relaxed.mean_movement;
    figures.max_movement = relaxed.max_movement;
    figures.failed_projections = relaxed.failed_projections;
    const detail::NearestNeighbourStatistics nearest =
        detail::nearest_neighbour_statistics(pointshell.points, end, spacing);
    figures.nearest_min = nearest.min;
    figures.nearest_max = nearest.max;
    figures.nearest_mean = nearest.mean;
    figures.nearest_ratio =
        nearest.min > 0.0 ? nearest.max / nearest.min : std::numeric_limits<double>::infinity();
    figures.nearest_percentile_1 = nearest.percentile_1;
    figures.nearest_percentile_99 = nearest.percentile_99;
    stage.finish();
  }

  pointshell.normals = inward_normals(normal_source, pointshell.points, options.progress);
  for (Eigen::Index s = 0; s < total; ++s) {
    if (!(std::abs(field.distance(pointshell.points.row(s).transpose()) - level) <= epsilon)) {
      summary.off_level_set.push_back(s);
    }
  }
  if (report != nullptr) *report = std::move(summary);
  return pointshell;
}

Pointshell repulsion_pointshell(const TriangleMesh& closed_mesh,
                                const DistanceFieldOptions& field_options,
                                const RepulsionOptions& options, RepulsionReport* report) {
  options.validate();
  DistanceFieldOptions with_progress = field_options;
  if (!with_progress.progress) with_progress.progress = options.progress;
  const DistanceGrid field = signed_distance_field(closed_mesh, with_progress);
  return repulsion_pointshell(field, 0.0, closed_mesh, options, report);
}

}  // namespace khz::contact
