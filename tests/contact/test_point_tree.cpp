#include <khz/contact/pointshell/nested_levels.hpp>
#include <khz/contact/pointshell/pointshell_sampling.hpp>
#include <khz/contact/tree/point_tree.hpp>
#include <khz/reduced/worker_threads.hpp>
#include <khz/test/generated_meshes.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <vector>

namespace khz::contact {
namespace {

/// Random samples on a unit sphere nested by farthest-point order.
Pointshell nested_sphere(Eigen::Index count, LevelSchedule schedule) {
  NestedLevelOptions options;
  options.schedule = schedule;
  return nested_pointshell(random_pointshell(test::uv_sphere(24, 12), count, 3), options);
}

/// 20000 points in ×4 levels from 20: large enough for several progress reports.
const Pointshell& large_sphere() {
  static const Pointshell shell = nested_sphere(20000, LevelSchedule::quadrupling(20));
  return shell;
}

/// The tree level of node n.
int level_of(const PointTree& tree, Eigen::Index n) {
  int level = 0;
  while (n >= tree.level_end(level)) ++level;
  return level;
}

/// Brute force: the points of the subtree of node n, by explicit recursion.
void collect_subtree(const PointTree& tree, Eigen::Index n, std::vector<Eigen::Index>& points) {
  const PointTreeNode& node = tree.node(n);
  points.push_back(node.point);
  for (Eigen::Index c = node.first_child; c < node.first_child + node.child_count; ++c) {
    collect_subtree(tree, c, points);
  }
}

class PointTreeStructure : public ::testing::TestWithParam<LevelSchedule> {};

TEST_P(PointTreeStructure, LevelsAreNestedAndChildrenContiguousInTraversalOrder) {
  const Pointshell input = nested_sphere(3000, GetParam());
  const PointTree tree(input);
  ASSERT_EQ(tree.num_levels(), input.num_levels());
  ASSERT_EQ(tree.num_points(), input.size());
  EXPECT_EQ(tree.level_begin(0), 0);
  for (int level = 0; level < tree.num_levels(); ++level) {
    // Lᵢ holds an instance of every point of pointshell levels 0…i.
    EXPECT_EQ(tree.level_end(level) - tree.level_begin(level), input.level_end(level)) << level;
  }
  EXPECT_EQ(tree.level_end(tree.num_levels() - 1), tree.num_nodes());
  EXPECT_EQ(tree.num_internal_nodes(), tree.level_begin(tree.num_levels() - 1));

  for (int level = 0; level < tree.num_levels(); ++level) {
    // The children of level i, in node order, are exactly level i+1.
    Eigen::Index next_child = tree.level_end(level);
    for (Eigen::Index n = tree.level_begin(level); n < tree.level_end(level); ++n) {
      const PointTreeNode& node = tree.node(n);
      EXPECT_EQ(node.parent < 0, level == 0);
      if (level + 1 == tree.num_levels()) {
        EXPECT_EQ(node.child_count, 0);
        EXPECT_EQ(node.first_child, -1);
        EXPECT_EQ(node.rest_radius, 0.0);
        continue;
      }
      ASSERT_GE(node.child_count, 1);
      EXPECT_EQ(node.first_child, next_child);
      next_child += node.child_count;
      // The first child is the node's own point again; the others are new on level i+1.
      EXPECT_EQ(tree.node(node.first_child).point, node.point);
      for (Eigen::Index c = node.first_child; c < node.first_child + node.child_count; ++c) {
        EXPECT_EQ(tree.node(c).parent, n);
        if (c > node.first_child) {
          EXPECT_GE(tree.node(c).point, tree.pointshell().level_begin(level + 1));
          EXPECT_LT(tree.node(c).point, tree.pointshell().level_end(level + 1));
        }
      }
    }
    if (level + 1 < tree.num_levels()) {
      EXPECT_EQ(next_child, tree.level_end(level + 1));
    }
  }
}

TEST_P(PointTreeStructure, PointsAreNumberedByFirstAppearanceAndLeavesHoldEachOnce) {
  const Pointshell input = nested_sphere(3000, GetParam());
  const PointTree tree(input);
  // Scanning the nodes in order, each new point is the next index.
  Eigen::Index seen = 0;
  for (Eigen::Index n = 0; n < tree.num_nodes(); ++n) {
    const Eigen::Index s = tree.node(n).point;
    ASSERT_LE(s, seen) << n;
    if (s == seen) {
      ++seen;
      // First instance iff the point is new on the node's level.
      EXPECT_GE(s, tree.pointshell().level_begin(level_of(tree, n)));
    } else {
      EXPECT_LT(s, tree.pointshell().level_begin(level_of(tree, n)));
    }
  }
  EXPECT_EQ(seen, tree.num_points());
  std::vector<int> leaf_count(static_cast<std::size_t>(tree.num_points()), 0);
  for (Eigen::Index n = tree.num_internal_nodes(); n < tree.num_nodes(); ++n) {
    ++leaf_count[static_cast<std::size_t>(tree.node(n).point)];
  }
  EXPECT_EQ(std::count(leaf_count.begin(), leaf_count.end(), 1), tree.num_points());

  // The tree's pointshell is the input with each level's points permuted.
  EXPECT_EQ(tree.pointshell().level_ends, input.level_ends);
  std::vector<bool> used(static_cast<std::size_t>(input.size()), false);
  for (Eigen::Index s = 0; s < tree.num_points(); ++s) {
    const Eigen::Index row = tree.source_index(s);
    ASSERT_FALSE(used[static_cast<std::size_t>(row)]);
    used[static_cast<std::size_t>(row)] = true;
    EXPECT_EQ(tree.pointshell().points.row(s), input.points.row(row));
    EXPECT_EQ(tree.pointshell().normals.row(s), input.normals.row(row));
    const auto level_of_point = [](const Pointshell& shell, Eigen::Index p) {
      int level = 0;
      while (p >= shell.level_end(level)) ++level;
      return level;
    };
    EXPECT_EQ(level_of_point(tree.pointshell(), s), level_of_point(input, row));
  }
}

TEST_P(PointTreeStructure, ParentIsTheNearestNodeOfTheLevelAbove) {
  const Pointshell input = nested_sphere(3000, GetParam());
  const PointTree tree(input);
  const PointMatrix& points = tree.pointshell().points;
  for (int level = 1; level < tree.num_levels(); ++level) {
    const Eigen::Index coarser = tree.pointshell().level_begin(level);
    for (Eigen::Index n = tree.level_begin(level); n < tree.level_end(level); ++n) {
      const PointTreeNode& node = tree.node(n);
      const Eigen::Index parent_point = tree.node(node.parent).point;
      if (node.point < coarser) {
        EXPECT_EQ(parent_point, node.point);  // a copy hangs under its own instance
        continue;
      }
      const double nearest = std::sqrt((points.topRows(coarser).rowwise() - points.row(node.point))
                                           .rowwise()
                                           .squaredNorm()
                                           .minCoeff());
      // Summation orders differ (Eigen's rowwise reduction): a few ulps.
      EXPECT_NEAR((points.row(parent_point) - points.row(node.point)).norm(), nearest,
                  4 * std::numeric_limits<double>::epsilon() * nearest)
          << n;
    }
  }
}

TEST_P(PointTreeStructure, RestRadiusIsTheLargestDistanceToTheSubtree) {
  const Pointshell input = nested_sphere(3000, GetParam());
  const PointTree tree(input);
  const PointMatrix& points = tree.pointshell().points;
  std::vector<Eigen::Index> subtree;
  for (Eigen::Index n = 0; n < tree.num_internal_nodes(); ++n) {
    subtree.clear();
    collect_subtree(tree, n, subtree);
    double largest = 0.0;
    for (const Eigen::Index s : subtree) {
      largest = std::max(largest, (points.row(s) - points.row(tree.node(n).point)).norm());
    }
    EXPECT_DOUBLE_EQ(tree.node(n).rest_radius, largest) << n;
  }
  // Radii shrink with depth: the largest radius per level falls (by ~2 per level for ×4
  // levels, ~2.8 for ×8).
  double previous = std::numeric_limits<double>::infinity();
  for (int level = 0; level + 1 < tree.num_levels(); ++level) {
    double largest = 0.0;
    for (Eigen::Index n = tree.level_begin(level); n < tree.level_end(level); ++n) {
      largest = std::max(largest, tree.node(n).rest_radius);
    }
    EXPECT_LT(largest, previous) << level;
    previous = largest;
  }
}

INSTANTIATE_TEST_SUITE_P(Schedules, PointTreeStructure,
                         ::testing::Values(LevelSchedule::branching(8),
                                           LevelSchedule::quadrupling(20), LevelSchedule{5, 3, 3}));

TEST(PointTree, HandlesOneLevelAndCoincidentPoints) {
  Pointshell flat = random_pointshell(test::unit_cube_surface(), 50, 1);
  const PointTree leaves_only(flat);
  EXPECT_EQ(leaves_only.num_levels(), 1);
  EXPECT_EQ(leaves_only.num_internal_nodes(), 0);
  EXPECT_EQ(leaves_only.num_nodes(), 50);

  // Level 1 repeats level 0's points: each copy is a new point at distance 0.
  Pointshell doubled;
  doubled.points.resize(100, 3);
  doubled.points << flat.points, flat.points;
  doubled.normals.resize(100, 3);
  doubled.normals << flat.normals, flat.normals;
  doubled.level_ends = {50, 100};
  const PointTree tree(doubled);
  EXPECT_EQ(tree.num_nodes(), 150);
  for (Eigen::Index n = 0; n < 50; ++n) {
    EXPECT_EQ(tree.node(n).child_count, 2);
    EXPECT_EQ(tree.node(n).rest_radius, 0.0);
  }
}

TEST(PointTree, GivesEveryPointAParentWhenDistancesOverflow) {
  // Finite points 1e200 m apart: every squared distance is infinite, and each new point still
  // gets a parent (the lowest index, as for a tie), not the index −1 (found by fuzz_tree).
  Pointshell far;
  far.points.resize(3, 3);
  far.points << 1e200, 0, 0, -1e200, 0, 0, 0, 1e200, 0;
  far.normals = Eigen::MatrixX3d::Zero(3, 3);
  far.normals.col(2).setOnes();
  far.level_ends = {1, 3};
  const PointTree tree(far);
  ASSERT_EQ(tree.num_nodes(), 4);
  EXPECT_EQ(tree.node(0).child_count, 3);
  for (Eigen::Index n = 1; n < 4; ++n) EXPECT_EQ(tree.node(n).parent, 0) << n;
}

TEST(PointTree, IsTheSameOnAnyThreadCount) {
  const Pointshell& input = large_sphere();
  const PointTree parallel(input);
  const PointTree serial = [&] {
    const reduced::ScopedWorkerThreads one(1);
    return PointTree(input);
  }();
  ASSERT_EQ(parallel.num_nodes(), serial.num_nodes());
  EXPECT_EQ(std::memcmp(parallel.nodes().data(), serial.nodes().data(),
                        sizeof(PointTreeNode) * static_cast<std::size_t>(serial.num_nodes())),
            0);
  EXPECT_EQ(parallel.pointshell().points, serial.pointshell().points);
}

TEST(PointTree, ReportsProgressAndRejectsInvalidPointshells) {
  const Pointshell& input = large_sphere();
  std::vector<std::string> stages;
  const PointTree tree(input, [&](const Progress& progress) {
    if (progress.done == 0) stages.emplace_back(progress.stage);
    EXPECT_LE(progress.done, progress.total);
    return true;
  });
  EXPECT_EQ(stages, (std::vector<std::string>{"point tree parents", "point tree radii"}));
  EXPECT_THROW(PointTree(input, [](const Progress& p) { return p.stage != "point tree radii"; }),
               Cancelled);

  Pointshell bad = input;
  bad.level_ends.back() -= 1;
  EXPECT_THROW(PointTree{bad}, Error);
  bad = input;
  bad.points(7, 0) = std::nan("");
  EXPECT_THROW(PointTree{bad}, Error);
}

}  // namespace
}  // namespace khz::contact
