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
        const float value = node(i, j, k);
        smallest = std::min(smallest, static_cast<double>(value));
        m_boundary_nodes_inside += value < 0.0f ? 1 : 0;
      }
    }
  }
  m_boundary_minimum = smallest - m_geometry.spacing / std::numbers::sqrt2;
}

std::int64_t DistanceGrid::boundary_node_count() const noexcept {
  const std::int64_t n = m_geometry.nodes_per_axis(), inner = m_geometry.cells - 1;
  return n * n * n - inner * inner * inner;
}

float DistanceGrid::node(int i, int j, int k) const noexcept {
  assert(i >= 0 && j >= 0 && k >= 0 && i <= m_geometry.cells && j <= m_geometry.cells &&
         k <= m_geometry.cells);
  return m_values[static_cast<std::size_t>(m_geometry.node_index(i, j, k))];
}

double DistanceGrid::outside(const Eigen::Vector3d& local,
                             Eigen::Vector3d* gradient) const noexcept {
  const auto cells = static_cast<double>(m_geometry.cells);
  const Eigen::Vector3d outward = local.cwiseMax(0.0).cwiseMin(cells);
  const Eigen::Vector3d offset = (local - outward) * m_geometry.spacing;
  const double to_box = offset.norm();
  if (gradient != nullptr) {
    *gradient = to_box > 0.0 ? Eigen::Vector3d(offset / to_box) : Eigen::Vector3d::Zero();
  }
  return to_box + m_boundary_minimum;
}

}  // namespace khz::contact
