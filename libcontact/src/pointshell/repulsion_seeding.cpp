#include "pointshell/repulsion_seeding.hpp"

#include <khz/contact/pointshell/pointshell_sampling.hpp>
#include <khz/reduced/worker_threads.hpp>

#include "pointshell/repulsion_projection.hpp"
#include "pointshell/split_mix.hpp"

#include <algorithm>
#include <utility>

namespace khz::contact::detail {

namespace {

constexpr int max_draws = 9;
// Below this many points a parallel loop costs more than it saves.
constexpr Eigen::Index parallel_threshold = 2048;

/// Interleaves the low 21 bits of x with two zero bits after each (Morton order).
std::uint64_t spread(std::uint64_t x) noexcept {
  x &= 0x1fffff;
  x = (x | x << 32) & 0x1f00000000ffffULL;
  x = (x | x << 16) & 0x1f0000ff0000ffULL;
  x = (x | x << 8) & 0x100f00f00f00f00fULL;
  x = (x | x << 4) & 0x10c30c30c30c30c3ULL;
  x = (x | x << 2) & 0x1249249249249249ULL;
  return x;
}

/// Reorders rows [begin, end) along a Morton curve over the field's grid cells, so that
/// particles near in space are near in memory and the repulsion's neighbour loads mostly hit
/// the cache: iterations 1.6× faster at 256k points (dino.off, one core). Reproducible: the
/// keys are unique per row.
void sort_spatially(const DistanceGrid& field, Eigen::Index begin, Eigen::Index end,
                    PointMatrix& points, std::vector<Eigen::Vector3d>& normals) {
  const GridGeometry& grid = field.geometry();
  std::vector<std::pair<std::uint64_t, Eigen::Index>> keyed;
  keyed.reserve(static_cast<std::size_t>(end - begin));
  for (Eigen::Index s = begin; s < end; ++s) {
    const Eigen::Vector3d cell = (points.row(s).transpose() - grid.origin) / grid.spacing;
    std::uint64_t key = 0;
    for (int axis = 0; axis < 3; ++axis) {
      const double clamped = std::clamp(cell[axis], 0.0, static_cast<double>(grid.cells));
      key |= spread(static_cast<std::uint64_t>(clamped)) << axis;
    }
    keyed.emplace_back(key, s);
  }
  std::sort(keyed.begin(), keyed.end());
  const PointMatrix old_points = points.middleRows(begin, end - begin);
  const std::vector<Eigen::Vector3d> old_normals(normals.begin() + begin, normals.begin() + end);
  for (std::size_t k = 0; k < keyed.size(); ++k) {
    const Eigen::Index from = keyed[k].second - begin;
    points.row(begin + static_cast<Eigen::Index>(k)) = old_points.row(from);
    normals[static_cast<std::size_t>(begin) + k] = old_normals[static_cast<std::size_t>(from)];
  }
}

}  // namespace

Eigen::Index seed_level(const DistanceGrid& field, const TriangleMesh& level_set,
                        const SeedingTarget& target, std::uint64_t seed, Eigen::Index begin,
                        Eigen::Index end, PointMatrix& points,
                        std::vector<Eigen::Vector3d>& normals) {
  // The rows still to place, in increasing order.
  std::vector<Eigen::Index> pending(static_cast<std::size_t>(end - begin));
  for (Eigen::Index s = begin; s < end; ++s) pending[static_cast<std::size_t>(s - begin)] = s;
  for (int draw = 0; draw < max_draws && !pending.empty(); ++draw) {
    const auto count = static_cast<Eigen::Index>(pending.size());
    const Pointshell samples =
        random_pointshell(level_set, count, split_mix(seed + static_cast<std::uint64_t>(draw)));
    std::vector<char> placed(pending.size(), 0);
#pragma omp parallel for num_threads(reduced::worker_threads()) \
    schedule(dynamic, 256) if (count > parallel_threshold)
    for (Eigen::Index k = 0; k < count; ++k) {
      const auto i = static_cast<std::size_t>(k);
      const Eigen::Vector3d sample = samples.points.row(k).transpose();
      const LevelSetProjection projected = project_onto_level_set(
          field, target.level, sample, target.projection_tolerance, target.projection_max_step);
      placed[i] = projected.converged ? 1 : 0;
      points.row(pending[i]) =
          projected.converged ? projected.point.transpose() : sample.transpose();
      normals[static_cast<std::size_t>(pending[i])] =
          projected.converged ? projected.normal
                              : Eigen::Vector3d(-samples.normals.row(k).transpose());
    }
    std::vector<Eigen::Index> left;
    for (std::size_t i = 0; i < pending.size(); ++i) {
      if (placed[i] == 0) left.push_back(pending[i]);
    }
    pending.swap(left);
  }
  sort_spatially(field, begin, end, points, normals);
  return static_cast<Eigen::Index>(pending.size());
}

}  // namespace khz::contact::detail
