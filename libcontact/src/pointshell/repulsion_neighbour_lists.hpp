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
    const auto begin = static_cast<std::size_t>(m_offsets[static_cast<std::size_t>(m)]);
    const auto end = static_cast<std::size_t>(m_offsets[static_cast<std::size_t>(m) + 1]);
    return {m_neighbours.data() + begin, end - begin};
  }

 private:
  std::vector<std::int64_t> m_offsets;  ///< Per particle, then the end.
  std::vector<std::int32_t> m_neighbours;
};

}  // namespace khz::contact::detail
