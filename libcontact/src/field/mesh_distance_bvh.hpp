#pragma once
// A bounding-volume hierarchy of a triangle mesh for exact closest-point searches: axis-aligned
// boxes built by a binned surface-area split, searched nearest child first and pruned by the
// distance to each box.

#include <khz/contact/common.hpp>

#include "field/mesh_distance_triangle.hpp"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <span>
#include <vector>

namespace khz::contact::detail {

/// A triangle as the searches read it: its corners (copied, in the tree's leaf order, so that a
/// leaf's triangles are adjacent in memory) and its index in the mesh.
struct BvhTriangle {
  Eigen::Vector3d a, b, c;
  int index = -1;           ///< Row of the mesh's triangle matrix.
  bool degenerate = false;  ///< is_degenerate_triangle(): searched through its edges only.

  TrianglePoint closest(const Eigen::Vector3d& p) const noexcept {
    return degenerate ? closest_on_degenerate_triangle(p, a, b, c)
                      : closest_on_triangle(p, a, b, c);
  }
  double squared_distance(const Eigen::Vector3d& p) const noexcept {
    return (p - closest(p).point).squaredNorm();
  }
};

/// What a search found.
struct BvhHit {
  int slot = -1;  ///< Position of the triangle in TriangleBvh::triangles().
  double squared_distance = 0.0;
  TrianglePoint closest;
};

/// The tree. Immutable after construction; searches are const, thread-safe and allocate
/// nothing.
class TriangleBvh {
 public:
  /// @param vertices, triangles a mesh that passed validate() and has at least one triangle.
  TriangleBvh(const PointMatrix& vertices, const TriangleMatrix& triangles);

  /// The triangles in leaf order; a hit's slot indexes this.
  std::span<const BvhTriangle> triangles() const noexcept { return m_triangles; }

  /// The closest triangle to p among those at squared distance ≤ max_squared_distance (may be
  /// infinite). `hint` (a slot, or −1) is tried first: a good guess, such as the answer for a
  /// nearby point, shrinks the search ball at once. Returns false, leaving `hit` unchanged,
  /// if no triangle is that close (or p is not finite). Among triangles at the same distance
  /// the first met wins.
  bool closest(const Eigen::Vector3d& p, double max_squared_distance, int hint,
               BvhHit& hit) const noexcept;

 private:
  /// A box; its children are nodes `first` and `first + 1` (count = 0), or it is a leaf holding
  /// triangles [first, first + count).
  struct Node {
    double lower[3];
    double upper[3];
    int first;
    int count;
  };

  struct BuildItem;
  /// Fills m_nodes[node] with the subtree of items [begin, end), appending leaves' triangles
  /// to m_triangles in depth-first order.
  void build(const PointMatrix& vertices, const TriangleMatrix& triangles,
             std::vector<BuildItem>& items, int node, int begin, int end, int depth);
  static double box_squared_distance(const Node& node, const Eigen::Vector3d& p) noexcept;

  std::vector<Node> m_nodes;
  std::vector<BvhTriangle> m_triangles;
};

}  // namespace khz::contact::detail
