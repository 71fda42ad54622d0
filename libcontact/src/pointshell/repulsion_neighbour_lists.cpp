#include "pointshell/repulsion_neighbour_lists.hpp"

#include "pointshell/repulsion_hash_grid.hpp"

#include <khz/reduced/worker_threads.hpp>

#include <omp.h>

#include <algorithm>

namespace khz::contact::detail {

namespace {

/// For each moving point (row first + m) of occupied cell `cell`: calls start(m), then found(j)
/// for each other point j within `reach` of it. The cell's 27 neighbours are looked up once for
/// all of its points.
template <typename Start, typename Found>
void pairs_in_cell(const RepulsionHashGrid& grid, std::size_t cell, Eigen::Index first,
                   double reach_squared, Start&& start, Found&& found) {
  const RepulsionHashGrid::Range own = grid.cell_slots(cell);
  const RepulsionHashGrid::Neighbourhood around = grid.neighbourhood(cell);
  for (std::int32_t slot = own.begin; slot < own.end; ++slot) {
    const std::int32_t self = grid.slot_point(slot);
    if (self < first) continue;
    start(self - first);
    const Eigen::Vector3d& p = grid.slot_position(slot);
    for (int r = 0; r < around.count; ++r) {
      const RepulsionHashGrid::Range range = around.ranges[static_cast<std::size_t>(r)];
      for (std::int32_t other = range.begin; other < range.end; ++other) {
        if (other != slot && (grid.slot_position(other) - p).squaredNorm() < reach_squared) {
          found(grid.slot_point(other));
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
  const auto moving = static_cast<std::size_t>(count - first);
  m_buffer_of.resize(moving);
  m_starts.resize(moving);
  m_counts.resize(moving);
  const int threads = reduced::worker_threads();
  m_buffers.resize(std::max<std::size_t>(m_buffers.size(), static_cast<std::size_t>(threads)));
#pragma omp parallel num_threads(threads) if (cells > 256)
  {
    const auto thread = static_cast<std::size_t>(omp_get_thread_num());
    std::vector<std::int32_t>& buffer = m_buffers[thread];
    buffer.clear();
    std::size_t m = 0;
#pragma omp for schedule(dynamic, 64)
    for (std::ptrdiff_t cell = 0; cell < cells; ++cell) {
      pairs_in_cell(
          grid, static_cast<std::size_t>(cell), first, reach_squared,
          [&](Eigen::Index row) {
            m = static_cast<std::size_t>(row);
            m_buffer_of[m] = static_cast<std::int32_t>(thread);
            m_starts[m] = buffer.size();
            m_counts[m] = 0;
          },
          [&](std::int32_t j) {
            buffer.push_back(j);
            ++m_counts[m];
          });
    }
  }
}

}  // namespace khz::contact::detail
