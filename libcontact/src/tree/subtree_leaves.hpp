#pragma once
// The leaves under each node of a nested point tree: one contiguous run of the last level,
// because the children of each level, in node order, are exactly the next level.

#include <khz/contact/tree/point_tree.hpp>

#include <cstdint>
#include <vector>

namespace khz::contact::detail {

/// Leaves (nodes of the last level) [begin, end) in the subtree of one node. Every point of a
/// node's subtree has an instance among them: each node's first child is its own point again.
struct LeafRange {
  std::int32_t begin = 0;
  std::int32_t end = 0;
};

/// The leaf range of every node, bottom-up in O(#nodes).
inline std::vector<LeafRange> subtree_leaves(const PointTree& tree) {
  std::vector<LeafRange> ranges(static_cast<std::size_t>(tree.num_nodes()));
  const int last = tree.num_levels() - 1;
  for (auto n = static_cast<std::int32_t>(tree.level_begin(last)); n < tree.num_nodes(); ++n) {
    ranges[static_cast<std::size_t>(n)] = {n, n + 1};
  }
  for (int level = last - 1; level >= 0; --level) {
    for (auto n = static_cast<std::int32_t>(tree.level_begin(level)); n < tree.level_end(level);
         ++n) {
      const PointTreeNode& node = tree.node(n);
      ranges[static_cast<std::size_t>(n)] = {
          ranges[static_cast<std::size_t>(node.first_child)].begin,
          ranges[static_cast<std::size_t>(node.first_child + node.child_count - 1)].end};
    }
  }
  return ranges;
}

}  // namespace khz::contact::detail
