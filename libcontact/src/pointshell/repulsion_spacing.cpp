#include "pointshell/repulsion_spacing.hpp"

#include "pointshell/repulsion_hash_grid.hpp"

#include <khz/reduced/worker_threads.hpp>

#include <algorithm>
#include <vector>

namespace khz::contact::detail {

namespace {

// Grid cells, in spacings. A relaxed level's nearest neighbours lie within 1.35 spacings, so
// with cells of 1.5 the search nearly always ends after the 27 cells around a point; with cells
// of one spacing a third of the points searched the next shell of 98 (dino.off, 262k points:
// 0.15 s against 0.23).
constexpr double cell_spacings = 1.5;

}  // namespace

NearestNeighbourStatistics nearest_neighbour_statistics(const PointMatrix& points,
                                                        Eigen::Index count, double spacing) {
  NearestNeighbourStatistics statistics;
  if (count < 2) return statistics;
  const RepulsionHashGrid grid(points, count, cell_spacings * spacing);
  std::vector<double> nearest(static_cast<std::size_t>(count));
#pragma omp parallel for num_threads(reduced::worker_threads()) \
    schedule(dynamic, 256) if (count > 2048)
  for (Eigen::Index s = 0; s < count; ++s) {
    nearest[static_cast<std::size_t>(s)] = grid.nearest_other(s, points.row(s).transpose()).second;
  }
  for (const double distance : nearest) statistics.mean += distance;
  statistics.mean /= static_cast<double>(count);
  const auto [lowest, highest] = std::minmax_element(nearest.begin(), nearest.end());
  statistics.min = *lowest;
  statistics.max = *highest;
  const auto at = [&](double fraction) {
    const auto rank = nearest.begin() +
                      static_cast<std::ptrdiff_t>(fraction * static_cast<double>(count - 1) + 0.5);
    std::nth_element(nearest.begin(), rank, nearest.end());
    return *rank;
  };
  statistics.percentile_1 = at(0.01);
  statistics.percentile_99 = at(0.99);
  return statistics;
}

}  // namespace khz::contact::detail
