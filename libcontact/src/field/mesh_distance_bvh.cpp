#include "field/mesh_distance_bvh.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace khz::contact::detail {
namespace {

/// Largest leaf the split always divides; leaves up to twice this size are kept when no split
/// pays off.
constexpr int leaf_size = 4;
/// Bins of the surface-area split.
constexpr int bin_count = 16;
/// Below this depth splits follow the surface-area heuristic; deeper ones halve the count, so
/// the depth stays below max_sah_depth + log2(#triangles) and the search stack cannot overflow.
constexpr int max_sah_depth = 48;
constexpr int stack_size = 128;

double half_area(const Eigen::AlignedBox3d& box) {
  if (box.isEmpty()) return 0.0;
  const Eigen::Vector3d size = box.sizes();
  return size.x() * size.y() + size.y() * size.z() + size.z() * size.x();
}

}  // namespace

struct TriangleBvh::BuildItem {
  Eigen::AlignedBox3d box;
  Eigen::Vector3d centroid;
  int index;
};

TriangleBvh::TriangleBvh(const PointMatrix& vertices, const TriangleMatrix& triangles) {
  const auto count = static_cast<int>(triangles.rows());
  std::vector<BuildItem> items(static_cast<std::size_t>(count));
  for (int t = 0; t < count; ++t) {
    BuildItem& item = items[static_cast<std::size_t>(t)];
    item.box.setEmpty();
    for (int corner = 0; corner < 3; ++corner) {
      item.box.extend(vertices.row(triangles(t, corner)).transpose());
    }
    item.centroid = item.box.center();
    item.index = t;
  }
  m_nodes.reserve(static_cast<std::size_t>(2 * count));
  m_triangles.reserve(static_cast<std::size_t>(count));
  m_nodes.push_back({});
  build(vertices, triangles, items, 0, 0, count, 0);
}

void TriangleBvh::build(const PointMatrix& vertices, const TriangleMatrix& triangles,
                        std::vector<BuildItem>& items, int node, int begin, int end, int depth) {
  Eigen::AlignedBox3d box;
  Eigen::AlignedBox3d centroids;
  box.setEmpty();
  centroids.setEmpty();
  for (int i = begin; i < end; ++i) {
    box.extend(items[static_cast<std::size_t>(i)].box);
    centroids.extend(items[static_cast<std::size_t>(i)].centroid);
  }
  for (int axis = 0; axis < 3; ++axis) {
    m_nodes[static_cast<std::size_t>(node)].lower[axis] = box.min()[axis];
    m_nodes[static_cast<std::size_t>(node)].upper[axis] = box.max()[axis];
  }
  const auto make_leaf = [&] {
    Node& leaf = m_nodes[static_cast<std::size_t>(node)];
    leaf.first = static_cast<int>(m_triangles.size());
    leaf.count = end - begin;
    for (int i = begin; i < end; ++i) {
      const int t = items[static_cast<std::size_t>(i)].index;
      BvhTriangle triangle;
      triangle.a = vertices.row(triangles(t, 0)).transpose();
      triangle.b = vertices.row(triangles(t, 1)).transpose();
      triangle.c = vertices.row(triangles(t, 2)).transpose();
      triangle.index = t;
      triangle.degenerate = is_degenerate_triangle(triangle.a, triangle.b, triangle.c);
      m_triangles.push_back(triangle);
    }
  };
  const int count = end - begin;
  if (count <= leaf_size) {
    make_leaf();
    return;
  }

  int axis = 0;
  centroids.sizes().maxCoeff(&axis);
  const double low = centroids.min()[axis];
  const double extent = centroids.sizes()[axis];
  int middle = -1;
  if (extent > 0.0 && depth < max_sah_depth) {
    // Binned surface-area heuristic: the cost of a split is the area-weighted triangle count of
    // its two sides, against count × area for keeping a leaf.
    std::array<Eigen::AlignedBox3d, bin_count> bin_boxes;
    std::array<int, bin_count> bin_counts{};
    for (auto& bin_box : bin_boxes) bin_box.setEmpty();
    const auto bin_of = [&](const BuildItem& item) {
      const int bin = static_cast<int>(bin_count * ((item.centroid[axis] - low) / extent));
      return std::clamp(bin, 0, bin_count - 1);
    };
    for (int i = begin; i < end; ++i) {
      const BuildItem& item = items[static_cast<std::size_t>(i)];
      const int bin = bin_of(item);
      bin_boxes[static_cast<std::size_t>(bin)].extend(item.box);
      ++bin_counts[static_cast<std::size_t>(bin)];
    }
    std::array<double, bin_count> right_cost{};
    Eigen::AlignedBox3d right;
    right.setEmpty();
    int right_count = 0;
    for (int bin = bin_count - 1; bin > 0; --bin) {
      right.extend(bin_boxes[static_cast<std::size_t>(bin)]);
      right_count += bin_counts[static_cast<std::size_t>(bin)];
      right_cost[static_cast<std::size_t>(bin)] = half_area(right) * right_count;
    }
    Eigen::AlignedBox3d left;
    left.setEmpty();
    int left_count = 0;
    int best_split = -1;
    double best_cost = std::numeric_limits<double>::infinity();
    for (int split = 1; split < bin_count; ++split) {
      left.extend(bin_boxes[static_cast<std::size_t>(split - 1)]);
      left_count += bin_counts[static_cast<std::size_t>(split - 1)];
      if (left_count == 0 || left_count == count) continue;
      const double cost =
          half_area(left) * left_count + right_cost[static_cast<std::size_t>(split)];
      if (cost < best_cost) {
        best_cost = cost;
        best_split = split;
      }
    }
    if (best_split >= 0 && count <= 2 * leaf_size && best_cost >= half_area(box) * count) {
      make_leaf();
      return;
    }
    if (best_split >= 0) {
      const auto split_at =
          std::partition(items.begin() + begin, items.begin() + end,
                         [&](const BuildItem& item) { return bin_of(item) < best_split; });
      middle = static_cast<int>(split_at - items.begin());
    }
  }
  if (middle <= begin || middle >= end) {
    // No useful split by position (coincident centroids, or too deep): halve the count.
    middle = begin + count / 2;
    std::nth_element(items.begin() + begin, items.begin() + middle, items.begin() + end,
                     [&](const BuildItem& x, const BuildItem& y) {
                       return x.centroid[axis] < y.centroid[axis];
                     });
  }
  const auto left = static_cast<int>(m_nodes.size());
  m_nodes.push_back({});
  m_nodes.push_back({});
  m_nodes[static_cast<std::size_t>(node)].first = left;
  m_nodes[static_cast<std::size_t>(node)].count = 0;
  build(vertices, triangles, items, left, begin, middle, depth + 1);
  build(vertices, triangles, items, left + 1, middle, end, depth + 1);
}

double TriangleBvh::box_squared_distance(const Node& node, const Eigen::Vector3d& p) noexcept {
  double sum = 0.0;
  for (int axis = 0; axis < 3; ++axis) {
    const double outside = std::max({node.lower[axis] - p[axis], p[axis] - node.upper[axis], 0.0});
    sum += outside * outside;
  }
  return sum;
}

bool TriangleBvh::closest(const Eigen::Vector3d& p, double max_squared_distance, int hint,
                          BvhHit& hit) const noexcept {
  double best = max_squared_distance;
  bool found = false;
  const auto consider = [&](int slot) {
    const TrianglePoint candidate = m_triangles[static_cast<std::size_t>(slot)].closest(p);
    const double squared = (p - candidate.point).squaredNorm();
    if (squared < best || (!found && squared <= best)) {
      best = squared;
      found = true;
      hit.slot = slot;
      hit.squared_distance = squared;
      hit.closest = candidate;
    }
  };
  if (hint >= 0) consider(hint);

  struct Pending {
    int node;
    double squared_distance;
  };
  Pending stack[stack_size];
  int top = 0;
  int node = 0;
  if (!(box_squared_distance(m_nodes[0], p) <= best)) return found;
  for (;;) {
    const Node& current = m_nodes[static_cast<std::size_t>(node)];
    if (current.count > 0) {
      for (int slot = current.first; slot < current.first + current.count; ++slot) {
        if (slot != hint) consider(slot);
      }
    } else {
      // Nearer child first; the farther one waits with its box distance for a second check.
      int near_child = current.first;
      int far_child = current.first + 1;
      double near_distance = box_squared_distance(m_nodes[static_cast<std::size_t>(near_child)], p);
      double far_distance = box_squared_distance(m_nodes[static_cast<std::size_t>(far_child)], p);
      if (far_distance < near_distance) {
        std::swap(near_child, far_child);
        std::swap(near_distance, far_distance);
      }
      if (far_distance <= best) stack[top++] = {far_child, far_distance};
      if (near_distance <= best) {
        node = near_child;
        continue;
      }
    }
    for (;;) {
      if (top == 0) return found;
      const Pending pending = stack[--top];
      if (pending.squared_distance <= best) {
        node = pending.node;
        break;
      }
    }
  }
}

}  // namespace khz::contact::detail
