#pragma once
// Disjoint sets over 0..n−1, used to group triangles, triangle corners and welded vertices.

#include <Eigen/Core>

#include <numeric>
#include <vector>

namespace khz::reduced::detail {

/// Disjoint-set forest whose roots are always the lowest element of their set, so callers get
/// a representative that does not depend on the order in which sets were joined.
class UnionFind {
 public:
  explicit UnionFind(Eigen::Index size) : m_parent(size) {
    std::iota(m_parent.begin(), m_parent.end(), Eigen::Index{0});
  }

  /// The lowest element of the set containing `element`.
  Eigen::Index find(Eigen::Index element) {
    while (m_parent[element] != element) {
      m_parent[element] = m_parent[m_parent[element]];  // path halving keeps trees shallow
      element = m_parent[element];
    }
    return element;
  }

  void unite(Eigen::Index a, Eigen::Index b) {
    a = find(a);
    b = find(b);
    if (a < b) {
      m_parent[b] = a;
    } else if (b < a) {
      m_parent[a] = b;
    }
  }

 private:
  std::vector<Eigen::Index> m_parent;
};

}  // namespace khz::reduced::detail
