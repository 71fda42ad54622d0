#pragma once
// The regular cubic grid a distance field is sampled on (thesis §3.11).

#include <khz/contact/export.hpp>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cstdint>

namespace khz::contact {

/// A cube of `cells`³ cells of edge `spacing`, with (cells + 1)³ nodes; node (i, j, k) sits at
/// origin + spacing · (i, j, k). Node indices run x fastest: (k · n + j) · n + i, n = cells + 1.
struct KHZ_CONTACT_API GridGeometry {
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();  ///< Lowest corner (m).
  double spacing = 1.0;                              ///< h (m), > 0.
  int cells = 1;                                     ///< Cells per axis, ≥ 1.

  /// The cube centred on `bounds` whose edge is `expansion` times the longest side of `bounds`,
  /// divided into `cells` per axis: the thesis's tight cube scaled about its centre (§3.11; the
  /// usual expansion is 1.5). @throws Error for an empty or non-finite box, expansion < 1, or
  /// cells < 1.
  static GridGeometry cube_around(const Eigen::AlignedBox3d& bounds, double expansion, int cells);

  /// @throws Error unless the origin is finite, spacing > 0 and finite, and cells ≥ 1.
  void validate() const;

  int nodes_per_axis() const noexcept { return cells + 1; }
  std::int64_t node_count() const noexcept {
    const auto n = static_cast<std::int64_t>(nodes_per_axis());
    return n * n * n;
  }
  /// Edge length of the cube (m).
  double size() const noexcept { return spacing * cells; }
  Eigen::AlignedBox3d box() const noexcept {
    return {origin, origin + Eigen::Vector3d::Constant(size())};
  }
  Eigen::Vector3d node_position(int i, int j, int k) const noexcept {
    return origin + spacing * Eigen::Vector3d(i, j, k);
  }
  std::int64_t node_index(int i, int j, int k) const noexcept {
    const auto n = static_cast<std::int64_t>(nodes_per_axis());
    return (k * n + j) * n + i;
  }
};

}  // namespace khz::contact
