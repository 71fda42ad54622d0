#include "fem/element_bvh.hpp"

#include <algorithm>
#include <cassert>
#include <numeric>
#include <utility>

namespace khz::reduced::detail {

namespace {
// Few enough elements that testing them all beats descending further.
constexpr int max_leaf_size = 4;
}  // namespace

ElementBvh::ElementBvh(std::vector<Eigen::AlignedBox3d> boxes) : m_boxes(std::move(boxes)) {
  assert(!m_boxes.empty());
  const int count = static_cast<int>(m_boxes.size());
  std::vector<Eigen::Vector3d> centres(m_boxes.size());
  for (int e = 0; e < count; ++e) centres[e] = m_boxes[e].center();
  m_order.resize(m_boxes.size());
  std::iota(m_order.begin(), m_order.end(), 0);
  m_nodes.reserve(2 * m_boxes.size());  // a binary tree with ≤ #elements leaves
  build(0, count, centres);
}

int ElementBvh::build(int begin, int end, const std::vector<Eigen::Vector3d>& centres) {
  const int index = static_cast<int>(m_nodes.size());
  m_nodes.emplace_back();
  Eigen::AlignedBox3d box;  // empty
  Eigen::AlignedBox3d centre_bounds;
  for (int k = begin; k < end; ++k) {
    box.extend(m_boxes[m_order[k]]);
    centre_bounds.extend(centres[m_order[k]]);
  }
  m_nodes[index].box = box;
  if (end - begin <= max_leaf_size) {
    m_nodes[index].first = begin;
    m_nodes[index].count = end - begin;
    return index;
  }
  // Median split: both halves get the same element count whatever the distribution, which
  // bounds the depth (and the query stack) by log2 of the element count.
  int axis = 0;
  centre_bounds.sizes().maxCoeff(&axis);
  const int middle = begin + (end - begin) / 2;
  std::nth_element(m_order.begin() + begin, m_order.begin() + middle, m_order.begin() + end,
                   [&](int a, int b) { return centres[a][axis] < centres[b][axis]; });
  build(begin, middle, centres);  // left child: index + 1
  const int right = build(middle, end, centres);
  m_nodes[index].first = right;  // m_nodes may have reallocated: index, not a reference
  m_nodes[index].count = 0;
  return index;
}

}  // namespace khz::reduced::detail
