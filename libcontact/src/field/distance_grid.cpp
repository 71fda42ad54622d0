#include <khz/contact/common.hpp>
#include <khz/contact/field/distance_grid.hpp>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>

namespace khz::contact {

DistanceGrid::DistanceGrid(const GridGeometry& geometry, std::vector<float> values, bool is_signed)
    : m_geometry(geometry), m_values(std::move(values)), m_signed(is_signed) {
  m_geometry.validate();
  if (static_cast<std::int64_t>(m_values.size()) != m_geometry.node_count()) {
    throw Error("DistanceGrid: expected " + std::to_string(m_geometry.node_count()) +
                " node values for " + std::to_string(m_geometry.cells) + "³ cells, got " +
                std::to_string(m_values.size()));
  }
  const auto bad = std::find_if(m_values.begin(), m_values.end(),
                                [](float value) { return !std::isfinite(value); });
  if (bad != m_values.end()) {
    throw Error("DistanceGrid: node value " + std::to_string(bad - m_values.begin()) +
                " is not finite");
  }
  m_inverse_spacing = 1.0 / m_geometry.spacing;
  // The boundary nodes: the six faces of the node cube.
  const int last = m_geometry.cells;
  double smallest = std::numeric_limits<double>::infinity();
  for (int k = 0; k <= last; ++k) {
    for (int j = 0; j <= last; ++j) {
      const bool face_kj = k == 0 || k == last || j == 0 || j == last;
      for (int i = 0; i <= last; i += face_kj ? 1 : last) {
        smallest = std::min(smallest, static_cast<double>(node(i, j, k)));
      }
    }
  }
  m_boundary_minimum = smallest - m_geometry.spacing / std::numbers::sqrt2;
}

float DistanceGrid::node(int i, int j, int k) const noexcept {
  assert(i >= 0 && j >= 0 && k >= 0 && i <= m_geometry.cells && j <= m_geometry.cells &&
         k <= m_geometry.cells);
  return m_values[static_cast<std::size_t>(m_geometry.node_index(i, j, k))];
}

namespace {

/// Trilinear interpolation at p inside the box, and with `with_gradient` its gradient: one body
/// for both queries, so that distance() returns bit for bit the value distance_and_gradient()
/// does, without paying for the derivatives.
template <bool with_gradient>
double interpolate(const GridGeometry& g, const float* values, double inverse_spacing,
                   const Eigen::Vector3d& local, Eigen::Vector3d* gradient) noexcept {
  // The cell's lowest node, clamped so that the box's upper faces use the last cell (the
  // power-of-two mantissa indexing of §3.11 was measured and left out: distance_grid.hpp).
  const int i = std::min(static_cast<int>(local.x()), g.cells - 1);
  const int j = std::min(static_cast<int>(local.y()), g.cells - 1);
  const int k = std::min(static_cast<int>(local.z()), g.cells - 1);
  const double x = local.x() - i, y = local.y() - j, z = local.z() - k;
  const std::int64_t n = g.nodes_per_axis();
  const float* c = values + g.node_index(i, j, k);
  const double c000 = c[0], c100 = c[1], c010 = c[n], c110 = c[n + 1];
  const double c001 = c[n * n], c101 = c[n * n + 1], c011 = c[n * n + n], c111 = c[n * n + n + 1];
  // Along x, then y, then z; the derivatives by the same products.
  const double c00 = c000 + x * (c100 - c000), c10 = c010 + x * (c110 - c010);
  const double c01 = c001 + x * (c101 - c001), c11 = c011 + x * (c111 - c011);
  const double c0 = c00 + y * (c10 - c00), c1 = c01 + y * (c11 - c01);
  if constexpr (with_gradient) {
    const double dx0 = (c100 - c000) + y * ((c110 - c010) - (c100 - c000));
    const double dx1 = (c101 - c001) + y * ((c111 - c011) - (c101 - c001));
    gradient->x() = (dx0 + z * (dx1 - dx0)) * inverse_spacing;
    gradient->y() = ((c10 - c00) + z * ((c11 - c01) - (c10 - c00))) * inverse_spacing;
    gradient->z() = (c1 - c0) * inverse_spacing;
  }
  return c0 + z * (c1 - c0);
}

}  // namespace

double DistanceGrid::distance(const Eigen::Vector3d& p) const noexcept {
  const Eigen::Vector3d local = (p - m_geometry.origin) * m_inverse_spacing;  // in cells
  const auto cells = static_cast<double>(m_geometry.cells);
  if (!(local.minCoeff() >= 0.0 && local.maxCoeff() <= cells)) {
    Eigen::Vector3d unused;
    return distance_and_gradient(p, unused);  // outside (or NaN): inequality 3.14
  }
  return interpolate<false>(m_geometry, m_values.data(), m_inverse_spacing, local, nullptr);
}

double DistanceGrid::distance_and_gradient(const Eigen::Vector3d& p,
                                           Eigen::Vector3d& gradient) const noexcept {
  const GridGeometry& g = m_geometry;
  const Eigen::Vector3d local = (p - g.origin) * m_inverse_spacing;  // in cells
  const auto cells = static_cast<double>(g.cells);
  if (!(local.minCoeff() >= 0.0 && local.maxCoeff() <= cells)) {
    // Outside (or NaN): inequality 3.14.
    const Eigen::Vector3d outward = local.cwiseMax(0.0).cwiseMin(cells);
    const Eigen::Vector3d offset = (local - outward) * g.spacing;
    const double to_box = offset.norm();
    gradient = to_box > 0.0 ? Eigen::Vector3d(offset / to_box) : Eigen::Vector3d::Zero();
    return to_box + m_boundary_minimum;
  }
  return interpolate<true>(g, m_values.data(), m_inverse_spacing, local, &gradient);
}

}  // namespace khz::contact
