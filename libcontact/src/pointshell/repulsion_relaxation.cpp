#include "pointshell/repulsion_relaxation.hpp"

#include "pointshell/repulsion_kernel.hpp"
#include "pointshell/repulsion_neighbour_lists.hpp"
#include "pointshell/repulsion_projection.hpp"

#include <khz/reduced/worker_threads.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <span>

namespace khz::contact::detail {

namespace {

// The Verlet skin, in units of R: lists hold the pairs within (1 + skin)R and last until some
// particle has moved skin·R/2, so no pair can come within R unseen. Measured on dino.off
// (65k points): 0.25 rebuilt the lists every 4 iterations, 0.75 every 11 and ran 25% faster;
// beyond, the longer lists cost what the rarer rebuilds save.
constexpr double skin_fraction = 0.75;
// A particle's η grows back by this factor per iteration, up to the initial η.
constexpr double step_recovery = 1.2;
// Below this many particles a parallel loop costs more than it saves (and, on a loaded
// machine, waits for a descheduled thread at every barrier).
constexpr Eigen::Index parallel_threshold = 2048;
// A fixed direction for particles at exactly the same position (random starting points
// coincide with probability zero, but the force must still be defined).
const Eigen::Vector3d coincident_direction = Eigen::Vector3d(2.0, 3.0, 6.0) / 7.0;

/// The repulsion on row `self` from its neighbours, tangent to the level set (normal `normal`).
Eigen::Vector3d repulsion_on(const PointMatrix& points, Eigen::Index self,
                             std::span<const std::int32_t> neighbours,
                             const Eigen::Vector3d& normal, double radius) noexcept {
  const Eigen::Vector3d p = points.row(self).transpose();
  const double inverse_radius = 1.0 / radius;
  Eigen::Vector3d total = Eigen::Vector3d::Zero();
  for (const std::int32_t j : neighbours) {
    const Eigen::Vector3d away = p - points.row(j).transpose();
    const double squared = away.squaredNorm();
    if (squared >= radius * radius) continue;
    const double distance = std::sqrt(squared);
    const Eigen::Vector3d direction =
        distance > 0.0 ? Eigen::Vector3d(away / distance)
                       : Eigen::Vector3d((j < self ? 1.0 : -1.0) * coincident_direction);
    total += repulsion_force(distance * inverse_radius) * direction;
  }
  return total - total.dot(normal) * normal;
}

}  // namespace

RelaxationResult relax_level(const DistanceGrid& field, PointMatrix& points, Eigen::Index frozen,
                             Eigen::Index count, std::vector<Eigen::Vector3d>& normals,
                             const RelaxationSettings& settings, reduced::StageProgress& progress) {
  const Eigen::Index moving = count - frozen;
  const auto size = static_cast<std::size_t>(moving);
  std::vector<Eigen::Vector3d> forces(size), previous_forces(size, Eigen::Vector3d::Zero());
  std::vector<double> steps(size, settings.step), movements(size), drifts(size);
  std::vector<char> failures(size);
  RepulsionNeighbourLists lists;
  const double skin = skin_fraction * settings.radius;
  PointMatrix anchors;  // the moving rows when the lists were built
  double drift = std::numeric_limits<double>::infinity();  // forces the first build

  RelaxationResult result;
  for (int iteration = 0; iteration < settings.max_iterations; ++iteration) {
    if (drift > 0.5 * skin) {
      lists.build(points, frozen, count, settings.radius + skin);
      anchors = points.middleRows(frozen, moving);
      drift = 0.0;
    }
    // 1. All forces at the current positions.
#pragma omp parallel for num_threads(reduced::worker_threads()) \
    schedule(dynamic, 256) if (moving > parallel_threshold)
    for (Eigen::Index m = 0; m < moving; ++m) {
      const Eigen::Index self = frozen + m;
      forces[static_cast<std::size_t>(m)] = repulsion_on(
          points, self, lists.of(m), normals[static_cast<std::size_t>(self)], settings.radius);
    }
    // 2. All moves, each projected back onto the level set.
#pragma omp parallel for num_threads(reduced::worker_threads()) \
    schedule(dynamic, 256) if (moving > parallel_threshold)
    for (Eigen::Index m = 0; m < moving; ++m) {
      const auto i = static_cast<std::size_t>(m);
      const Eigen::Index self = frozen + m;
      const Eigen::Vector3d& force = forces[i];
      steps[i] = force.dot(previous_forces[i]) < 0.0
                     ? 0.5 * steps[i]
                     : std::min(settings.step, step_recovery * steps[i]);
      previous_forces[i] = force;
      Eigen::Vector3d move = steps[i] * force;
      const double length = move.norm();
      if (length > settings.max_move) move *= settings.max_move / length;
      const Eigen::Vector3d old = points.row(self).transpose();
      const LevelSetProjection projected =
          project_onto_level_set(field, settings.level, old + move, settings.projection_tolerance,
                                 settings.projection_max_step);
      failures[i] = projected.converged ? 0 : 1;
      if (projected.converged) {
        movements[i] = (projected.point - old).norm();
        points.row(self) = projected.point.transpose();
        normals[static_cast<std::size_t>(self)] = projected.normal;
      } else {
        movements[i] = 0.0;
        steps[i] *= 0.5;
      }
      drifts[i] = (points.row(self) - anchors.row(m)).norm();
    }
    // Serial sums: the same bits on any thread count.
    result = RelaxationResult{};
    for (std::size_t i = 0; i < size; ++i) {
      result.mean_step += steps[i];
      result.mean_movement += movements[i];
      result.max_movement = std::max(result.max_movement, movements[i]);
      result.failed_projections += failures[i];
      drift = std::max(drift, drifts[i]);
    }
    const double divisor = static_cast<double>(std::max<Eigen::Index>(moving, 1));
    result.mean_step /= divisor;
    result.mean_movement /= divisor;
    result.iterations = iteration + 1;
    progress.advance();
    // Particles that cannot move do not count as settled: at most 1% may fail.
    if (result.mean_movement < settings.tolerance * settings.spacing &&
        100 * result.failed_projections <= moving) {
      result.converged = true;
      break;
    }
  }
  return result;
}

}  // namespace khz::contact::detail
