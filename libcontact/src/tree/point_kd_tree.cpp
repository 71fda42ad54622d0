#include "tree/point_kd_tree.hpp"

#include <algorithm>
#include <cassert>
#include <limits>

namespace khz::contact::detail {

PointKdTree::PointKdTree(const Eigen::Ref<const PointMatrix>& points, Eigen::Index count) {
  assert(count >= 1 && count <= points.rows());
  m_slot_points.resize(static_cast<std::size_t>(count));
  m_slot_positions.resize(static_cast<std::size_t>(count));
  for (std::int32_t s = 0; s < static_cast<std::int32_t>(count); ++s) {
    m_slot_points[static_cast<std::size_t>(s)] = s;
    m_slot_positions[static_cast<std::size_t>(s)] = points.row(s).transpose();
  }
  // A balanced tree of buckets holding ≥ leaf_size/2 points has < 4·count/leaf_size nodes.
  m_nodes.reserve(static_cast<std::size_t>(4 * count / leaf_size + 1));
  build(0, static_cast<std::int32_t>(count), -1);
  for (std::size_t slot = 0; slot < m_slot_points.size(); ++slot) {
    m_slot_positions[slot] = points.row(m_slot_points[slot]).transpose();
  }
}

std::int32_t PointKdTree::build(std::int32_t begin, std::int32_t end, std::int32_t parent) {
  const auto id = static_cast<std::int32_t>(m_nodes.size());
  m_nodes.emplace_back();
  Node node;
  node.begin = begin;
  node.end = end;
  node.parent = parent;
  node.lower = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  node.upper = -node.lower;
  const auto position = [this](std::int32_t slot) -> const Eigen::Vector3d& {
    return m_slot_positions[static_cast<std::size_t>(
        m_slot_points[static_cast<std::size_t>(slot)])];
  };
  for (std::int32_t slot = begin; slot < end; ++slot) {
    node.lower = node.lower.cwiseMin(position(slot));
    node.upper = node.upper.cwiseMax(position(slot));
  }
  const auto first = m_slot_points.begin() + begin;
  const auto last = m_slot_points.begin() + end;
  if (end - begin <= leaf_size) {
    std::sort(first, last);
  } else {
    int axis = 0;
    (node.upper - node.lower).maxCoeff(&axis);
    // (coordinate, index) is a strict total order: the split sets, hence the tree, are unique.
    const auto before = [this, axis](std::int32_t a, std::int32_t b) {
      const double ca = m_slot_positions[static_cast<std::size_t>(a)][axis];
      const double cb = m_slot_positions[static_cast<std::size_t>(b)][axis];
      return ca < cb || (ca == cb && a < b);
    };
    const std::int32_t middle = begin + (end - begin) / 2;
    std::nth_element(first, m_slot_points.begin() + middle, last, before);
    node.left = build(begin, middle, id);
    node.right = build(middle, end, id);
  }
  m_nodes[static_cast<std::size_t>(id)] = node;
  return id;
}

Eigen::Index PointKdTree::nearest(const Eigen::Vector3d& p) const noexcept {
  double best_squared = std::numeric_limits<double>::infinity();
  std::int32_t best = -1;
  nearest_in(0, p, best_squared, best);
  return best;
}

void PointKdTree::nearest_in(std::int32_t id, const Eigen::Vector3d& p, double& best_squared,
                             std::int32_t& best) const noexcept {
  const Node& node = m_nodes[static_cast<std::size_t>(id)];
  // Strictly farther only: an equally near point with a lower index may still be inside.
  if (node.distance_squared(p) > best_squared) return;
  if (node.is_leaf()) {
    for (std::int32_t slot = node.begin; slot < node.end; ++slot) {
      const auto s = static_cast<std::size_t>(slot);
      const double d = (m_slot_positions[s] - p).squaredNorm();
      // best < 0: the first point seen, even at a distance that overflows to infinity (points
      // 1e200 m apart are finite but their squared distance is not).
      if (best < 0 || d < best_squared || (d == best_squared && m_slot_points[s] < best)) {
        best_squared = d;
        best = m_slot_points[s];
      }
    }
    return;
  }
  const Node& left = m_nodes[static_cast<std::size_t>(node.left)];
  const Node& right = m_nodes[static_cast<std::size_t>(node.right)];
  if (left.distance_squared(p) <= right.distance_squared(p)) {
    nearest_in(node.left, p, best_squared, best);
    nearest_in(node.right, p, best_squared, best);
  } else {
    nearest_in(node.right, p, best_squared, best);
    nearest_in(node.left, p, best_squared, best);
  }
}

}  // namespace khz::contact::detail
