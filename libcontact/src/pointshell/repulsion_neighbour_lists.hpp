#pragma once
// Verlet neighbour lists for particle repulsion: the pairs within the kernel's radius plus a
// skin, found with the hash grid and reused until some particle has moved half the skin.

#include <khz/contact/common.hpp>

#include <Eigen/Core>

#include <cstdint>
#include <span>
#include <vector>

namespace khz::contact::detail {

/// For each particle of rows [first, count) of a point matrix, the other rows of [0, count)
/// within `reach` when the lists were built, in an order fixed by coordinates and indices.
class RepulsionNeighbourLists {
 public:
  /// (Re)builds the lists, in parallel (OpenMP) and reproducibly. Preconditions: 0 ≤ first ≤
  /// count ≤ points.rows() < 2³¹, finite points, reach > 0.
  void build(const PointMatrix& points, Eigen::Index first, Eigen::Index count, double reach);

  /// The neighbours of row first + m.
  std::span<const std::int32_t> of(Eigen::Index m) const noexcept {
    const auto i = static_cast<std::size_t>(m);
    return {m_buffers[static_cast<std::size_t>(m_buffer_of[i])].data() + m_starts[i],
            static_cast<std::size_t>(m_counts[i])};
  }

 private:
  // One pass finds each particle's list and appends it to its thread's buffer: laying the
  // lists out in row order took a counting pass that searched every pair twice (a build of
  // 197k particles on dino.off: 68 ms against 116). Kept between builds for their capacity.
  std::vector<std::vector<std::int32_t>> m_buffers;  ///< Per thread.
  std::vector<std::int32_t> m_buffer_of;             ///< Per particle: its list's buffer …
  std::vector<std::size_t> m_starts;                 ///< … where the list starts in it …
  std::vector<std::int32_t> m_counts;                ///< … and its length.
};

}  // namespace khz::contact::detail
