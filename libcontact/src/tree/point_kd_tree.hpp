#pragma once
// A k-d tree over a prefix of a point set: the nearest-neighbour queries that link the levels of
// the nested point tree (thesis §3.9), and the boxes that prune farthest-point ordering (§3.9.1).

#include <khz/contact/common.hpp>

#include <Eigen/Core>

#include <cstdint>
#include <vector>

namespace khz::contact::detail {

/// A k-d tree with tight boxes and buckets of at most `leaf_size` points. Immutable after
/// construction; const queries are thread-safe.
///
/// The layout depends only on the coordinates and indices of the points (splits order points by
/// coordinate, then index; each bucket lists its points by index), not on the standard library's
/// partitioning, so everything built on it is reproducible across platforms.
class PointKdTree {
 public:
  static constexpr int leaf_size = 8;

  struct Node {
    Eigen::Vector3d lower;  ///< Tight box of the node's points (m).
    Eigen::Vector3d upper;
    std::int32_t begin = 0;   ///< The node's points are slots [begin, end).
    std::int32_t end = 0;     ///<
    std::int32_t left = -1;   ///< Children; −1 for a bucket (leaf).
    std::int32_t right = -1;  ///<
    std::int32_t parent = -1;

    bool is_leaf() const noexcept { return left < 0; }
    /// Squared distance from p to the box (0 inside).
    double distance_squared(const Eigen::Vector3d& p) const noexcept {
      return (lower - p).cwiseMax(p - upper).cwiseMax(0.0).squaredNorm();
    }
  };

  /// Builds the tree over rows [0, count) of `points` in O(count log count).
  /// Preconditions (the callers check them): 1 ≤ count ≤ points.rows() < 2³¹, finite points.
  PointKdTree(const Eigen::Ref<const PointMatrix>& points, Eigen::Index count);

  /// The index of the point nearest to p; among equally near points the lowest index (also when
  /// the squared distances overflow to infinity: never −1).
  Eigen::Index nearest(const Eigen::Vector3d& p) const noexcept;

  /// Node 0 is the root.
  const std::vector<Node>& nodes() const noexcept { return m_nodes; }
  /// The point index in each slot: buckets are contiguous runs of slots.
  const std::vector<std::int32_t>& slot_points() const noexcept { return m_slot_points; }
  /// The position of the point in each slot, copied in slot order for locality.
  const std::vector<Eigen::Vector3d>& slot_positions() const noexcept { return m_slot_positions; }

 private:
  std::int32_t build(std::int32_t begin, std::int32_t end, std::int32_t parent);
  void nearest_in(std::int32_t node, const Eigen::Vector3d& p, double& best_squared,
                  std::int32_t& best) const noexcept;

  std::vector<Node> m_nodes;
  std::vector<std::int32_t> m_slot_points;
  std::vector<Eigen::Vector3d> m_slot_positions;
};

}  // namespace khz::contact::detail
