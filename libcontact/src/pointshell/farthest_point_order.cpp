#include <khz/contact/pointshell/farthest_point_order.hpp>

#include <khz/reduced/stage_progress.hpp>
#include "tree/point_kd_tree.hpp"

#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <tuple>
#include <utility>

namespace khz::contact {

namespace {

using detail::PointKdTree;

// Points ordered between two progress reports.
constexpr std::int64_t report_interval = 1 << 14;

/// The running state of farthest-point sampling on a k-d tree: per slot the squared distance to
/// the nearest chosen point (−1 once the slot's point is chosen itself, so it is never the
/// maximum again), per node the largest such value among its slots.
class FarthestPointSampler {
 public:
  explicit FarthestPointSampler(const PointKdTree& tree)
      : m_tree(tree),
        m_nodes(tree.nodes()),
        m_positions(tree.slot_positions()),
        m_distance(tree.slot_positions().size(), std::numeric_limits<double>::infinity()),
        m_largest(tree.nodes().size(), std::numeric_limits<double>::infinity()) {}

  /// The slot holding `point`.
  std::int32_t slot_of(Eigen::Index point) const {
    const auto& points = m_tree.slot_points();
    for (std::size_t slot = 0; slot < points.size(); ++slot) {
      if (points[slot] == point) return static_cast<std::int32_t>(slot);
    }
    return -1;
  }

  /// A not yet chosen point farthest from the chosen ones, as its bucket and slot: a descent
  /// towards the larger maximum (the left child on ties), then the first slot holding it.
  std::pair<std::int32_t, std::int32_t> farthest() const noexcept {
    std::int32_t id = 0;
    while (!m_nodes[index(id)].is_leaf()) {
      const Node& node = m_nodes[index(id)];
      id = m_largest[index(node.left)] >= m_largest[index(node.right)] ? node.left : node.right;
    }
    std::int32_t slot = m_nodes[index(id)].begin;
    while (m_distance[index(slot)] != m_largest[index(id)]) ++slot;
    return {id, slot};
  }

  /// The bucket holding `slot`.
  std::int32_t bucket_of(std::int32_t slot) const noexcept {
    std::int32_t id = 0;
    while (!m_nodes[index(id)].is_leaf()) {
      const Node& node = m_nodes[index(id)];
      id = slot < m_nodes[index(node.left)].end ? node.left : node.right;
    }
    return id;
  }

  /// Squared distance of `slot` to the chosen set (+∞ before the first choice).
  double distance_squared(std::int32_t slot) const noexcept { return m_distance[index(slot)]; }

  /// Adds the point in `slot` of bucket `leaf` to the chosen set.
  void choose(std::int32_t leaf, std::int32_t slot) noexcept {
    m_distance[index(slot)] = -1.0;
    // Refresh the maxima on the chosen point's path first: update() may skip its bucket (when
    // every point there is already at distance 0, i.e. coincident points).
    std::int32_t id = leaf;
    refresh_leaf(id);
    for (id = m_nodes[index(id)].parent; id >= 0; id = m_nodes[index(id)].parent) {
      refresh_inner(id);
    }
    update(0, m_positions[index(slot)]);
  }

 private:
  using Node = PointKdTree::Node;

  static std::size_t index(std::int32_t i) noexcept { return static_cast<std::size_t>(i); }

  void refresh_leaf(std::int32_t id) noexcept {
    const Node& node = m_nodes[index(id)];
    double largest = -1.0;
    for (std::int32_t slot = node.begin; slot < node.end; ++slot) {
      largest = std::max(largest, m_distance[index(slot)]);
    }
    m_largest[index(id)] = largest;
  }

  void refresh_inner(std::int32_t id) noexcept {
    const Node& node = m_nodes[index(id)];
    m_largest[index(id)] = std::max(m_largest[index(node.left)], m_largest[index(node.right)]);
  }

  // Lowers the distances of the points that are nearer to c than to every chosen point. A node
  // whose box is at least as far from c as its largest distance holds no such point.
  void update(std::int32_t id, const Eigen::Vector3d& c) noexcept {
    const Node& node = m_nodes[index(id)];
    if (m_largest[index(id)] <= node.distance_squared(c)) return;
    if (node.is_leaf()) {
      double largest = -1.0;
      for (std::int32_t slot = node.begin; slot < node.end; ++slot) {
        double& distance = m_distance[index(slot)];
        distance = std::min(distance, (m_positions[index(slot)] - c).squaredNorm());
        largest = std::max(largest, distance);
      }
      m_largest[index(id)] = largest;
      return;
    }
    update(node.left, c);
    update(node.right, c);
    refresh_inner(id);
  }

  const PointKdTree& m_tree;
  const std::vector<Node>& m_nodes;
  const std::vector<Eigen::Vector3d>& m_positions;
  std::vector<double> m_distance;
  std::vector<double> m_largest;
};

}  // namespace

FarthestPointOrder farthest_point_order(const Eigen::Ref<const PointMatrix>& points,
                                        Eigen::Index first, const ProgressCallback& progress) {
  const Eigen::Index count = points.rows();
  if (count == 0) throw Error("farthest_point_order: no points");
  if (count >= Eigen::Index{std::numeric_limits<std::int32_t>::max()}) {
    throw Error("farthest_point_order: " + std::to_string(count) + " points, at most 2^31 - 2");
  }
  if (first < 0 || first >= count) {
    throw Error("farthest_point_order: first point " + std::to_string(first) + " is not in [0, " +
                std::to_string(count) + ")");
  }
  for (Eigen::Index s = 0; s < count; ++s) {
    if (!points.row(s).allFinite()) {
      throw Error("farthest_point_order: point " + std::to_string(s) + " is not finite");
    }
  }

  reduced::StageProgress stage(progress, "farthest-point order", count);
  const PointKdTree tree(points, count);
  FarthestPointSampler sampler(tree);
  FarthestPointOrder result;
  result.order.reserve(static_cast<std::size_t>(count));
  result.radii.reserve(static_cast<std::size_t>(count));

  std::int32_t slot = sampler.slot_of(first);
  std::int32_t leaf = sampler.bucket_of(slot);
  for (Eigen::Index k = 0; k < count; ++k) {
    if (k > 0) std::tie(leaf, slot) = sampler.farthest();
    result.order.push_back(tree.slot_points()[static_cast<std::size_t>(slot)]);
    result.radii.push_back(std::sqrt(sampler.distance_squared(slot)));
    sampler.choose(leaf, slot);
    if ((k + 1) % report_interval == 0) stage.advance(report_interval);
  }
  stage.finish();
  return result;
}

}  // namespace khz::contact
