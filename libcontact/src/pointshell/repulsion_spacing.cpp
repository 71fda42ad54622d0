#include "pointshell/repulsion_spacing.hpp"

#include "pointshell/repulsion_hash_grid.hpp"

#include <khz/reduced/worker_threads.hpp>

#include <algorithm>
#include <vector>

namespace khz::contact::detail {

NearestNeighbourStatistics nearest_neighbour_statistics(const PointMatrix& points,
                                                        Eigen::Index count, double cell_size) {
  NearestNeighbourStatistics statistics;
  if (count < 2) return statistics;
  const RepulsionHashGrid grid(points, count, cell_size);
  std::vector<double> nearest(static_cast<std::size_t>(count));
#pragma omp parallel for num_threads(reduced::worker_threads()) \
    schedule(dynamic, 256) if (count > 2048)
  for (Eigen::Index s = 0; s < count; ++s) {
    nearest[static_cast<std::size_t>(s)] = grid.nearest_other(s, points.row(s).transpose()).second;
  }
  for (const double distance : nearest) statistics.mean += distance;
  statistics.mean /= static_cast<double>(count);
  std::sort(nearest.begin(), nearest.end());
  const auto at = [&](double fraction) {
    return nearest[static_cast<std::size_t>(fraction * static_cast<double>(count - 1) + 0.5)];
  };
  statistics.min = nearest.front();
  statistics.max = nearest.back();
  statistics.percentile_1 = at(0.01);
  statistics.percentile_99 = at(0.99);
  return statistics;
}

}  // namespace khz::contact::detail
