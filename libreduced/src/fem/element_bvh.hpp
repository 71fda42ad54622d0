#pragma once
// Bounding-volume hierarchy over the axis-aligned boxes of a volume mesh's elements: the search
// structure behind MeshEmbedding (thesis §2.5.2: finding the element that carries a point).

#include <Eigen/Geometry>

#include <array>
#include <limits>
#include <utility>
#include <vector>

namespace khz::reduced::detail {

/// A binary tree over boxes, built once by median splits along the longest axis of the box
/// centres and stored in flat arrays (nodes in depth-first order, the left child right after
/// its parent). Immutable after construction, so queries may run concurrently.
class ElementBvh {
 public:
  /// Builds the tree over `boxes` (box i bounds element i); `boxes` must not be empty.
  explicit ElementBvh(std::vector<Eigen::AlignedBox3d> boxes);

  /// Calls visit(element) for every element whose box contains `x` (boxes are closed), in tree
  /// order, until visit returns true ("stop").
  template <typename Visit>
  void visit_containing(const Eigen::Vector3d& x, Visit&& visit) const;

  /// The element nearest to `x` and its squared distance, where squared_distance(element)
  /// returns the exact squared distance (≥ 0) from x to that element. Boxes give lower bounds,
  /// so only elements whose box is no farther than the best element so far are measured. Ties
  /// go to the lower element index, so the answer does not depend on traversal order.
  struct Nearest {
    int element = -1;
    double squared_distance = std::numeric_limits<double>::infinity();
  };
  template <typename SquaredDistance>
  Nearest nearest(const Eigen::Vector3d& x, SquaredDistance&& squared_distance) const;

 private:
  struct Node {
    Eigen::AlignedBox3d box;
    int first = 0;  ///< Leaf: offset into m_order. Inner node: index of the right child.
    int count = 0;  ///< Leaf: number of elements (> 0). Inner node: 0.
  };

  int build(int begin, int end, const std::vector<Eigen::Vector3d>& centres);

  // Median splits halve the element count at every level, so the depth is at most
  // log2(#elements) + 1 ≤ 32 for int indices; a fixed stack avoids allocating in queries.
  static constexpr int max_depth = 64;

  std::vector<Eigen::AlignedBox3d> m_boxes;  ///< Per element.
  std::vector<int> m_order;                  ///< Element indices, grouped by leaf.
  std::vector<Node> m_nodes;                 ///< Root at index 0.
};

template <typename Visit>
void ElementBvh::visit_containing(const Eigen::Vector3d& x, Visit&& visit) const {
  std::array<int, max_depth> stack;
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& node = m_nodes[stack[--top]];
    if (!node.box.contains(x)) continue;
    if (node.count == 0) {
      const int self = static_cast<int>(&node - m_nodes.data());
      stack[top++] = node.first;
      stack[top++] = self + 1;  // left child first: pushed last
      continue;
    }
    for (int k = node.first; k < node.first + node.count; ++k) {
      const int element = m_order[k];
      if (m_boxes[element].contains(x) && visit(element)) return;
    }
  }
}

template <typename SquaredDistance>
ElementBvh::Nearest ElementBvh::nearest(const Eigen::Vector3d& x,
                                        SquaredDistance&& squared_distance) const {
  struct Pending {
    int node;
    double bound;  ///< Squared distance from x to the node's box: a lower bound for its elements.
  };
  std::array<Pending, max_depth> stack;
  int top = 0;
  stack[top++] = {0, m_nodes[0].box.squaredExteriorDistance(x)};
  Nearest best;
  while (top > 0) {
    const Pending pending = stack[--top];
    if (pending.bound > best.squared_distance) continue;  // best improved since it was pushed
    const Node& node = m_nodes[pending.node];
    if (node.count == 0) {
      Pending left{pending.node + 1, m_nodes[pending.node + 1].box.squaredExteriorDistance(x)};
      Pending right{node.first, m_nodes[node.first].box.squaredExteriorDistance(x)};
      if (left.bound < right.bound) std::swap(left, right);  // nearer child on top, popped first
      if (left.bound <= best.squared_distance) stack[top++] = left;
      if (right.bound <= best.squared_distance) stack[top++] = right;
      continue;
    }
    for (int k = node.first; k < node.first + node.count; ++k) {
      const int element = m_order[k];
      if (m_boxes[element].squaredExteriorDistance(x) > best.squared_distance) continue;
      const double d2 = squared_distance(element);
      if (d2 < best.squared_distance ||
          (d2 == best.squared_distance && (best.element < 0 || element < best.element))) {
        best = {element, d2};
      }
    }
  }
  return best;
}

}  // namespace khz::reduced::detail
