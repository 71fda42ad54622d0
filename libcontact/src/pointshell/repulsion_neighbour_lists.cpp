#include "pointshell/repulsion_neighbour_lists.hpp"

#include "pointshell/repulsion_hash_grid.hpp"

#include <khz/reduced/worker_threads.hpp>

namespace khz::contact::detail {

namespace {

/// Calls found(m, j) for each moving point (row first + m) of occupied cell `cell` and each
/// other point j within `reach` of it. The cell's 27 neighbours are looked up once for all of
/// its points.
template <typename Found>
void pairs_in_cell(const RepulsionHashGrid& grid, std::size_t cell, Eigen::Index first,
                   double reach_squared, Found&& found) {
  const RepulsionHashGrid::Range own = grid.cell_slots(cell);
  const RepulsionHashGrid::Neighbourhood around = grid.neighbourhood(cell);
  for (std::int32_t slot = own.begin; slot < own.end; ++slot) {
    const std::int32_t self = grid.slot_point(slot);
    if (self < first) continue;
    const Eigen::Vector3d& p = grid.slot_position(slot);
    for (int r = 0; r < around.count; ++r) {
      const RepulsionHashGrid::Range range = around.ranges[static_cast<std::size_t>(r)];
      for (std::int32_t other = range.begin; other < range.end; ++other) {
        if (other != slot && (grid.slot_position(other) - p).squaredNorm() < reach_squared) {
          found(self - first, grid.slot_point(other));
        }
      }
    }
  }
}

}  // namespace

void RepulsionNeighbourLists::build(const PointMatrix& points, Eigen::Index first,
                                    Eigen::Index count, double reach) {
  const RepulsionHashGrid grid(points, count, reach);
  const auto cells = static_cast<std::ptrdiff_t>(grid.cell_count());
  const double reach_squared = reach * reach;
  // Two passes, counting then filling, so each list lands at an offset fixed by the ones before
  // it whatever thread computes it.
  m_offsets.assign(static_cast<std::size_t>(count - first) + 1, 0);
#pragma omp parallel for num_threads(reduced::worker_threads()) \
    schedule(dynamic, 64) if (cells > 256)
  for (std::ptrdiff_t cell = 0; cell < cells; ++cell) {
    pairs_in_cell(
        grid, static_cast<std::size_t>(cell), first, reach_squared,
        [&](Eigen::Index m, std::int32_t) { ++m_offsets[static_cast<std::size_t>(m) + 1]; });
  }
  for (std::size_t m = 0; m + 1 < m_offsets.size(); ++m) m_offsets[m + 1] += m_offsets[m];
  m_neighbours.resize(static_cast<std::size_t>(m_offsets.back()));
  std::vector<std::int64_t> next(m_offsets.begin(), m_offsets.end() - 1);
#pragma omp parallel for num_threads(reduced::worker_threads()) \
    schedule(dynamic, 64) if (cells > 256)
  for (std::ptrdiff_t cell = 0; cell < cells; ++cell) {
    pairs_in_cell(grid, static_cast<std::size_t>(cell), first, reach_squared,
                  [&](Eigen::Index m, std::int32_t j) {
                    m_neighbours[static_cast<std::size_t>(next[static_cast<std::size_t>(m)]++)] = j;
                  });
  }
}

}  // namespace khz::contact::detail
