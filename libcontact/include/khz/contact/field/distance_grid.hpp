#pragma once
// A distance field sampled on a regular cubic grid, queried by trilinear interpolation
// (thesis §3.11).

#include <khz/contact/export.hpp>
#include <khz/contact/field/detail/multiply_add.hpp>
#include <khz/contact/field/grid_geometry.hpp>

#include <Eigen/Core>

#include <algorithm>
#include <cstdint>
#include <span>
#include <vector>

namespace khz::contact {

/// Distance values (float, metres) at the nodes of a GridGeometry: signed (negative inside) or
/// unsigned. Immutable after construction; queries are thread-safe, allocation-free and satisfy
/// the DistanceField concept.
///
/// Inside the grid's box, distance() interpolates the eight nodes of the cell trilinearly.
/// Outside, the distance is not known; distance() returns the conservative lower bound of
/// inequality 3.14, d(p) ≥ d_box(p) + d_boundary, with d_box the distance from p to the box and
/// d_boundary = boundary_minimum(), so that a contact query culling by it never misses contact
/// and points far from the box are culled early.
///
/// Speed (bench_distance_field, BM_DistanceGridLookup, 129³ nodes, one core of this project's
/// Xeon): distance() about 61 M queries/s at random points of the box, 70 M/s at points within
/// a few cells of each other; distance_and_gradient() 55 and 65 M/s. The IEEE-mantissa voxel
/// indexing of thesis §3.11 (for 2^k cells, cell index and fraction read from the mantissa of
/// 1 + w, no float-to-int conversion) was measured against this code's truncation in the same
/// loop: 64 against 66 M/s from memory, 74 against 72 M/s in cache. The conversion stalls no
/// pipeline on current CPUs, so the trick is left out.
class KHZ_CONTACT_API DistanceGrid {
 public:
  /// @param values geometry.node_count() node values, x fastest (GridGeometry::node_index()).
  /// @param is_signed whether the values are signed distances (negative inside) rather than
  ///        unsigned ones; it only describes them (files, VTK export, soups).
  /// @throws Error if the geometry is invalid, the value count does not match, or a value is not
  ///         finite.
  DistanceGrid(const GridGeometry& geometry, std::vector<float> values, bool is_signed);

  const GridGeometry& geometry() const noexcept { return m_geometry; }
  /// h (m): the spacing of the grid, below which the field resolves no detail (a
  /// CellSizedDistanceField).
  double cell_size() const noexcept { return m_geometry.spacing; }
  bool is_signed() const noexcept { return m_signed; }
  /// All node values, x fastest.
  std::span<const float> values() const noexcept { return m_values; }
  /// The value at node (i, j, k); indices are not checked (asserted in debug builds).
  float node(int i, int j, int k) const noexcept;

  /// d_boundary of inequality 3.14: a lower bound of the distance anywhere on the box's surface,
  /// the smallest boundary node value less the largest distance from a point of a boundary face
  /// to its nearest node (h/√2), since a distance function changes no faster than the distance
  /// travelled.
  double boundary_minimum() const noexcept { return m_boundary_minimum; }
  /// Nodes on the box's six faces with a negative value. A signed field over a box around its
  /// surface with a margin (GridGeometry::cube_around with expansion > 1, as the field builders
  /// make it) has none: any is a sign error, the mark of a mesh whose inside is undefined (open,
  /// self-intersecting, inverted triangles) or of a box that does not surround it.
  std::int64_t boundary_nodes_inside() const noexcept { return m_boundary_nodes_inside; }
  /// The number of nodes on the box's six faces: (cells + 1)³ − (cells − 1)³.
  std::int64_t boundary_node_count() const noexcept;

  /// Trilinear value inside the box (its surface included); the bound of inequality 3.14
  /// outside. Inline: the contact query's inner loop.
  double distance(const Eigen::Vector3d& p) const noexcept {
    const Eigen::Vector3d local = (p - m_geometry.origin) * m_inverse_spacing;  // in cells
    if (!inside(local)) return outside(local, nullptr);
    return interpolate<false>(local, nullptr);
  }
  /// Asks the cache for the node values distance(p) will read (four cache lines), so that a
  /// caller with many points can overlap their memory latency. Does nothing outside the box.
  void prefetch(const Eigen::Vector3d& p) const noexcept {
    const Eigen::Vector3d local = (p - m_geometry.origin) * m_inverse_spacing;
    if (!inside(local)) return;
    const std::int64_t n = m_geometry.nodes_per_axis();
    const float* c =
        m_values.data() +
        m_geometry.node_index(std::min(static_cast<int>(local.x()), m_geometry.cells - 1),
                              std::min(static_cast<int>(local.y()), m_geometry.cells - 1),
                              std::min(static_cast<int>(local.z()), m_geometry.cells - 1));
    __builtin_prefetch(c);
    __builtin_prefetch(c + n);
    __builtin_prefetch(c + n * n);
    __builtin_prefetch(c + n * n + n);
  }
  /// Whether p (m) lies in the grid's box (its surface included), where distance() interpolates;
  /// false for NaN.
  bool contains(const Eigen::Vector3d& p) const noexcept {
    return inside((p - m_geometry.origin) * m_inverse_spacing);
  }
  /// distance(p), and in `gradient` the gradient of the returned function: of the trilinear
  /// interpolant inside (continuous within a cell, not across cell faces), of d_box outside
  /// (the unit vector from the box towards p).
  double distance_and_gradient(const Eigen::Vector3d& p, Eigen::Vector3d& gradient) const noexcept {
    const Eigen::Vector3d local = (p - m_geometry.origin) * m_inverse_spacing;  // in cells
    if (!inside(local)) return outside(local, &gradient);
    return interpolate<true>(local, &gradient);
  }

 private:
  /// Whether `local` (in cells from the origin) lies in the box; false for NaN.
  bool inside(const Eigen::Vector3d& local) const noexcept {
    return local.minCoeff() >= 0.0 && local.maxCoeff() <= static_cast<double>(m_geometry.cells);
  }
  /// The bound of inequality 3.14 at `local` outside the box (or NaN), and its gradient.
  double outside(const Eigen::Vector3d& local, Eigen::Vector3d* gradient) const noexcept;

  /// Trilinear interpolation at `local` inside the box, and with `with_gradient` its gradient:
  /// one body for both queries, so that distance() returns bit for bit the value
  /// distance_and_gradient() does, without paying for the derivatives. The value's every
  /// multiply-add is spelled with multiply_add(), so the two instantiations round it alike
  /// whatever the compiler would fuse in each (the derivatives are free to differ in the last
  /// bits between builds).
  template <bool with_gradient>
  double interpolate(const Eigen::Vector3d& local, Eigen::Vector3d* gradient) const noexcept {
    const GridGeometry& g = m_geometry;
    // The cell's lowest node, clamped so that the box's upper faces use the last cell (the
    // power-of-two mantissa indexing of §3.11 was measured and left out: see above).
    const int i = std::min(static_cast<int>(local.x()), g.cells - 1);
    const int j = std::min(static_cast<int>(local.y()), g.cells - 1);
    const int k = std::min(static_cast<int>(local.z()), g.cells - 1);
    const double x = local.x() - i, y = local.y() - j, z = local.z() - k;
    const std::int64_t n = g.nodes_per_axis();
    const float* c = m_values.data() + g.node_index(i, j, k);
    const double c000 = c[0], c100 = c[1], c010 = c[n], c110 = c[n + 1];
    const double c001 = c[n * n], c101 = c[n * n + 1], c011 = c[n * n + n];
    const double c111 = c[n * n + n + 1];
    // Along x, then y, then z; the derivatives by the same products.
    using detail::multiply_add;
    const double c00 = multiply_add(x, c100 - c000, c000);
    const double c10 = multiply_add(x, c110 - c010, c010);
    const double c01 = multiply_add(x, c101 - c001, c001);
    const double c11 = multiply_add(x, c111 - c011, c011);
    const double c0 = multiply_add(y, c10 - c00, c00), c1 = multiply_add(y, c11 - c01, c01);
    if constexpr (with_gradient) {
      const double dx0 = (c100 - c000) + y * ((c110 - c010) - (c100 - c000));
      const double dx1 = (c101 - c001) + y * ((c111 - c011) - (c101 - c001));
      gradient->x() = (dx0 + z * (dx1 - dx0)) * m_inverse_spacing;
      gradient->y() = ((c10 - c00) + z * ((c11 - c01) - (c10 - c00))) * m_inverse_spacing;
      gradient->z() = (c1 - c0) * m_inverse_spacing;
    }
    return multiply_add(z, c1 - c0, c0);
  }

  GridGeometry m_geometry;
  std::vector<float> m_values;
  bool m_signed;
  double m_boundary_minimum;
  std::int64_t m_boundary_nodes_inside = 0;
  double m_inverse_spacing;
};

}  // namespace khz::contact
