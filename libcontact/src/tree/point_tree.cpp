#include <khz/contact/tree/point_tree.hpp>

#include <khz/reduced/stage_progress.hpp>
#include <khz/reduced/worker_threads.hpp>
#include "tree/point_kd_tree.hpp"
#include "tree/subtree_leaves.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

namespace khz::contact {

namespace {

// Points per progress report and parallel loop: a nearest-neighbour query takes ~1 µs.
constexpr Eigen::Index chunk_size = 1 << 14;

std::size_t index(Eigen::Index i) noexcept { return static_cast<std::size_t>(i); }

/// For every point new on a level i ≥ 1, the nearest point of levels 0…i−1 (thesis §3.9); −1 for
/// level-0 points.
std::vector<std::int32_t> nearest_coarser_points(const Pointshell& pointshell,
                                                 const ProgressCallback& progress) {
  std::vector<std::int32_t> nearest(index(pointshell.size()), -1);
  reduced::StageProgress stage(progress, "point tree parents",
                               pointshell.size() - pointshell.level_end(0));
  for (int level = 1; level < pointshell.num_levels(); ++level) {
    const detail::PointKdTree coarser(pointshell.points, pointshell.level_begin(level));
    for (Eigen::Index begin = pointshell.level_begin(level); begin < pointshell.level_end(level);
         begin += chunk_size) {
      const Eigen::Index end = std::min(pointshell.level_end(level), begin + chunk_size);
#pragma omp parallel for num_threads(reduced::worker_threads()) schedule(static)
      for (Eigen::Index s = begin; s < end; ++s) {
        nearest[index(s)] =
            static_cast<std::int32_t>(coarser.nearest(pointshell.points.row(s).transpose()));
      }
      stage.advance(end - begin);
    }
  }
  stage.finish();
  return nearest;
}

}  // namespace

PointTree::PointTree(const Pointshell& pointshell, const ProgressCallback& progress) {
  validate(pointshell);
  const int levels = pointshell.num_levels();
  const Eigen::Index count = pointshell.size();
  Eigen::Index node_count = 0;
  for (int level = 0; level < levels; ++level) node_count += pointshell.level_end(level);
  if (node_count >= Eigen::Index{std::numeric_limits<std::int32_t>::max()}) {
    throw Error("PointTree: " + std::to_string(node_count) + " nodes, at most 2^31 - 2");
  }
  const std::vector<std::int32_t> nearest = nearest_coarser_points(pointshell, progress);

  // Layout, level by level: each node of level i is followed on level i+1 by its copy, then the
  // new points whose nearest coarser point it is (in input order), numbered as they appear.
  m_nodes.reserve(index(node_count));
  m_source_index.resize(index(count));
  std::int32_t next_point = 0;
  const auto add_point = [&](std::int32_t row) {
    m_source_index[index(next_point)] = row;
    return next_point++;
  };
  for (auto row = 0; row < pointshell.level_end(0); ++row) {
    m_nodes.push_back(PointTreeNode{add_point(row), -1, -1, 0, 0.0});
  }
  m_level_begin = {0, static_cast<std::int32_t>(m_nodes.size())};
  std::vector<std::int32_t> group_begin;  // per coarser input row: its new points, CSR
  std::vector<std::int32_t> group_rows;
  for (int level = 1; level < levels; ++level) {
    const Eigen::Index coarser = pointshell.level_begin(level);
    group_begin.assign(index(coarser + 1), 0);
    for (Eigen::Index row = coarser; row < pointshell.level_end(level); ++row) {
      ++group_begin[index(nearest[index(row)] + 1)];
    }
    for (Eigen::Index c = 0; c < coarser; ++c) group_begin[index(c + 1)] += group_begin[index(c)];
    group_rows.resize(index(pointshell.level_end(level) - coarser));
    std::vector<std::int32_t> fill(group_begin.begin(), group_begin.end() - 1);
    for (Eigen::Index row = coarser; row < pointshell.level_end(level); ++row) {
      group_rows[index(fill[index(nearest[index(row)])]++)] = static_cast<std::int32_t>(row);
    }
    const std::int32_t parents_end = m_level_begin.back();
    for (std::int32_t parent = m_level_begin[index(level - 1)]; parent < parents_end; ++parent) {
      const std::int32_t point = m_nodes[index(parent)].point;
      const auto first_child = static_cast<std::int32_t>(m_nodes.size());
      m_nodes.push_back(PointTreeNode{point, parent, -1, 0, 0.0});
      const std::int32_t row = m_source_index[index(point)];
      for (std::int32_t g = group_begin[index(row)]; g < group_begin[index(row + 1)]; ++g) {
        m_nodes.push_back(PointTreeNode{add_point(group_rows[index(g)]), parent, -1, 0, 0.0});
      }
      m_nodes[index(parent)].first_child = first_child;
      m_nodes[index(parent)].child_count = static_cast<std::int32_t>(m_nodes.size()) - first_child;
    }
    m_level_begin.push_back(static_cast<std::int32_t>(m_nodes.size()));
  }

  m_pointshell.points.resize(count, 3);
  m_pointshell.normals.resize(count, 3);
  for (Eigen::Index s = 0; s < count; ++s) {
    m_pointshell.points.row(s) = pointshell.points.row(m_source_index[index(s)]);
    m_pointshell.normals.row(s) = pointshell.normals.row(m_source_index[index(s)]);
  }
  m_pointshell.level_ends = pointshell.level_ends;

  // Rest radii: the exact maximum over the subtree's leaves, which hold all its points.
  const std::vector<detail::LeafRange> leaves = detail::subtree_leaves(*this);
  const PointMatrix& points = m_pointshell.points;
  reduced::StageProgress stage(progress, "point tree radii", num_internal_nodes());
  for (int level = 0; level + 1 < levels; ++level) {
    const auto begin = static_cast<std::int32_t>(level_begin(level));
    const auto end = static_cast<std::int32_t>(level_end(level));
#pragma omp parallel for num_threads(reduced::worker_threads()) schedule(dynamic, 16)
    for (std::int32_t n = begin; n < end; ++n) {
      PointTreeNode& node = m_nodes[index(n)];
      const Eigen::RowVector3d centre = points.row(node.point);
      double largest = 0.0;
      for (std::int32_t leaf = leaves[index(n)].begin; leaf < leaves[index(n)].end; ++leaf) {
        largest =
            std::max(largest, (points.row(m_nodes[index(leaf)].point) - centre).squaredNorm());
      }
      node.rest_radius = std::sqrt(largest);
    }
    stage.advance(end - begin);
  }
  stage.finish();
}

}  // namespace khz::contact
