#include <khz/contact/pointshell/farthest_point_order.hpp>
#include <khz/contact/pointshell/nested_levels.hpp>
#include <khz/contact/pointshell/pointshell_sampling.hpp>
#include <khz/reduced/mesh/surface_area.hpp>
#include <khz/test/generated_meshes.hpp>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <numeric>
#include <random>
#include <vector>

namespace khz::contact {
namespace {

/// Random points on a unit sphere mesh, one flat level.
Pointshell sphere_samples(Eigen::Index count, std::uint64_t seed = 1) {
  return random_pointshell(test::uv_sphere(32, 16), count, seed);
}

/// Brute force: the largest distance from any of `points` to its nearest among `centres`.
double covering_radius(const PointMatrix& points, const PointMatrix& centres) {
  double largest = 0.0;
  for (Eigen::Index s = 0; s < points.rows(); ++s) {
    const double nearest = (centres.rowwise() - points.row(s)).rowwise().squaredNorm().minCoeff();
    largest = std::max(largest, nearest);
  }
  return std::sqrt(largest);
}

/// Brute force: the smallest distance between two of `points`.
double separation(const PointMatrix& points) {
  double smallest = std::numeric_limits<double>::infinity();
  for (Eigen::Index a = 0; a < points.rows(); ++a) {
    for (Eigen::Index b = a + 1; b < points.rows(); ++b) {
      smallest = std::min(smallest, (points.row(a) - points.row(b)).squaredNorm());
    }
  }
  return std::sqrt(smallest);
}

PointMatrix rows_of(const PointMatrix& points, const std::vector<Eigen::Index>& order,
                    Eigen::Index count) {
  PointMatrix selected(count, 3);
  for (Eigen::Index k = 0; k < count; ++k) {
    selected.row(k) = points.row(order[static_cast<std::size_t>(k)]);
  }
  return selected;
}

/// The textbook O(N²) farthest-point sampling, first index on ties.
std::vector<Eigen::Index> naive_order(const PointMatrix& points, Eigen::Index first) {
  const Eigen::Index n = points.rows();
  Eigen::VectorXd nearest = Eigen::VectorXd::Constant(n, std::numeric_limits<double>::infinity());
  std::vector<Eigen::Index> order{first};
  std::vector<bool> chosen(static_cast<std::size_t>(n), false);
  for (Eigen::Index k = 1; k <= n; ++k) {
    const Eigen::Index last = order.back();
    chosen[static_cast<std::size_t>(last)] = true;
    Eigen::Index next = -1;
    for (Eigen::Index s = 0; s < n; ++s) {
      nearest[s] = std::min(nearest[s], (points.row(s) - points.row(last)).squaredNorm());
      if (!chosen[static_cast<std::size_t>(s)] && (next < 0 || nearest[s] > nearest[next])) {
        next = s;
      }
    }
    if (k < n) order.push_back(next);
  }
  return order;
}

TEST(FarthestPointOrder, MatchesTheQuadraticAlgorithm) {
  const Pointshell shell = sphere_samples(2000);
  const FarthestPointOrder fast = farthest_point_order(shell.points, 17);
  EXPECT_EQ(fast.order, naive_order(shell.points, 17));
}

TEST(FarthestPointOrder, RadiiAreTheCoveringRadiiAndSeparationsOfThePrefixes) {
  const Pointshell shell = sphere_samples(6000);
  const FarthestPointOrder result = farthest_point_order(shell.points, 0);
  ASSERT_EQ(result.order.size(), 6000u);
  ASSERT_EQ(result.radii.size(), 6000u);
  std::vector<Eigen::Index> sorted = result.order;
  std::sort(sorted.begin(), sorted.end());
  for (Eigen::Index k = 0; k < 6000; ++k) ASSERT_EQ(sorted[static_cast<std::size_t>(k)], k);
  EXPECT_EQ(result.order[0], 0);
  EXPECT_EQ(result.radii[0], std::numeric_limits<double>::infinity());
  EXPECT_TRUE(std::is_sorted(result.radii.rbegin(), result.radii.rend()));
  for (const Eigen::Index k : {1, 2, 3, 8, 72, 100, 584, 1000, 2000}) {
    const double radius = result.radii[static_cast<std::size_t>(k)];
    // The same quantity, summed in another order: equal to a few ulps.
    EXPECT_DOUBLE_EQ(covering_radius(shell.points, rows_of(shell.points, result.order, k)), radius)
        << k;
    if (k <= 1000) {
      EXPECT_GE(separation(rows_of(shell.points, result.order, k + 1)), radius) << k;
    }
  }
}

TEST(FarthestPointOrder, DependsOnGeometryNotOnInputOrder) {
  // Random points have no distance ties: shuffling the input gives the same sequence of points.
  const Pointshell shell = sphere_samples(3000);
  std::vector<Eigen::Index> shuffle(3000);
  std::iota(shuffle.begin(), shuffle.end(), Eigen::Index{0});
  std::shuffle(shuffle.begin(), shuffle.end(), std::mt19937(5));
  const PointMatrix shuffled = rows_of(shell.points, shuffle, 3000);
  const FarthestPointOrder a = farthest_point_order(shell.points, shuffle[0]);
  const FarthestPointOrder b = farthest_point_order(shuffled, 0);
  for (std::size_t k = 0; k < 3000; ++k) {
    ASSERT_EQ(shuffle[static_cast<std::size_t>(b.order[k])], a.order[k]) << k;
    EXPECT_EQ(a.radii[k], b.radii[k]);
  }
}

TEST(FarthestPointOrder, OrdersCoincidentPointsLast) {
  const Pointshell shell = sphere_samples(500);
  PointMatrix doubled(1000, 3);
  doubled << shell.points, shell.points;
  const FarthestPointOrder result = farthest_point_order(doubled, 3);
  std::vector<Eigen::Index> sorted = result.order;
  std::sort(sorted.begin(), sorted.end());
  for (Eigen::Index k = 0; k < 1000; ++k) ASSERT_EQ(sorted[static_cast<std::size_t>(k)], k);
  // The first 500 are one copy of each point, then the copies at distance 0.
  std::vector<bool> seen(500, false);
  for (std::size_t k = 0; k < 500; ++k) {
    const auto point = static_cast<std::size_t>(result.order[k] % 500);
    EXPECT_FALSE(seen[point]) << k;
    seen[point] = true;
    if (k > 0) {
      EXPECT_GT(result.radii[k], 0.0);
    }
  }
  for (std::size_t k = 500; k < 1000; ++k) EXPECT_EQ(result.radii[k], 0.0);
}

TEST(FarthestPointOrder, ReportsProgressAndRejectsBadInput) {
  const Pointshell shell = sphere_samples(40000);
  std::vector<std::int64_t> done;
  farthest_point_order(shell.points, 0, [&](const Progress& progress) {
    EXPECT_EQ(progress.stage, "farthest-point order");
    EXPECT_EQ(progress.total, 40000);
    done.push_back(progress.done);
    return true;
  });
  ASSERT_GE(done.size(), 3u);
  EXPECT_EQ(done.front(), 0);
  EXPECT_EQ(done.back(), 40000);
  EXPECT_TRUE(std::is_sorted(done.begin(), done.end()));
  EXPECT_THROW(farthest_point_order(shell.points, 0, [](const Progress& p) { return p.done == 0; }),
               Cancelled);
  EXPECT_THROW(farthest_point_order(PointMatrix(0, 3), 0), Error);
  EXPECT_THROW(farthest_point_order(shell.points, -1), Error);
  EXPECT_THROW(farthest_point_order(shell.points, 40000), Error);
  PointMatrix bad = shell.points.topRows(10);
  bad(4, 2) = std::numeric_limits<double>::infinity();
  EXPECT_THROW(farthest_point_order(bad, 0), Error);
}

TEST(LevelEnds, FollowTheSchedule) {
  using Ends = std::vector<Eigen::Index>;
  EXPECT_EQ(level_ends(1000, LevelSchedule::branching(8)), (Ends{8, 72, 584, 1000}));
  EXPECT_EQ(level_ends(584, LevelSchedule::branching(8)), (Ends{8, 72, 584}));
  EXPECT_EQ(level_ends(1000, LevelSchedule::quadrupling(10)), (Ends{10, 50, 210, 850, 1000}));
  EXPECT_EQ(level_ends(1000, {8, 8, 2}), (Ends{8, 1000}));
  EXPECT_EQ(level_ends(5, LevelSchedule::branching(8)), (Ends{5}));
  EXPECT_EQ(level_ends(1, {1, 2, 0}), (Ends{1}));
  // Sizes that would overflow saturate: the level is the last one.
  EXPECT_EQ(level_ends(Eigen::Index{1} << 40, {Eigen::Index{1} << 39, 1 << 30, 0}),
            (Ends{Eigen::Index{1} << 39, Eigen::Index{1} << 40}));
  EXPECT_THROW(level_ends(0, {}), Error);
  EXPECT_THROW(level_ends(10, {0, 8, 0}), Error);
  EXPECT_THROW(level_ends(10, {8, 1, 0}), Error);
  EXPECT_THROW(level_ends(10, {8, 8, -1}), Error);
}

TEST(NestedPointshell, LevelsArePrefixesThatCoverTheSurfaceEverFiner) {
  const TriangleMesh sphere = test::uv_sphere(32, 16);
  const Pointshell flat = random_pointshell(sphere, 4000, 2);
  NestedLevelOptions options;
  options.schedule = LevelSchedule::quadrupling(12);
  options.seed = 9;
  const Pointshell nested = nested_pointshell(flat, options);
  validate(nested);
  EXPECT_EQ(nested.level_ends, level_ends(4000, options.schedule));
  ASSERT_EQ(nested.num_levels(), 5);  // 12, 48, 192, 768, the remaining 2980

  // The same points with the same normals, reordered: random points are distinct, so sorting
  // both by position must pair them up.
  const auto by_position = [](const Pointshell& shell) {
    std::vector<std::array<double, 6>> rows;
    for (Eigen::Index s = 0; s < shell.size(); ++s) {
      rows.push_back({shell.points(s, 0), shell.points(s, 1), shell.points(s, 2),
                      shell.normals(s, 0), shell.normals(s, 1), shell.normals(s, 2)});
    }
    std::sort(rows.begin(), rows.end());
    return rows;
  };
  EXPECT_EQ(by_position(nested), by_position(flat));

  // Each prefix of levels covers all points at a radius that shrinks level by level, and at
  // most as coarsely as a packing allows: the k points of a prefix are r-separated (FPS), so
  // k caps of chordal radius r/2 are disjoint; on a sphere such a cap has area π(r/2)²
  // (Archimedes), so r ≤ 2√(A/(πk)) — with 5% for the inscribed mesh's points. Measured ratios
  // to that bound: 0.73, 0.67, 0.65, 0.59.
  const double area = reduced::surface_area(sphere);
  double previous = std::numeric_limits<double>::infinity();
  for (int level = 0; level + 1 < nested.num_levels(); ++level) {
    const Eigen::Index k = nested.level_end(level);
    const double radius = covering_radius(nested.points, nested.points.topRows(k));
    const double packing_bound = 2 * std::sqrt(area / (std::numbers::pi * static_cast<double>(k)));
    EXPECT_LT(radius, previous) << level;
    EXPECT_LT(radius, 1.05 * packing_bound) << level;
    previous = radius;
  }
}

TEST(NestedPointshell, IsReproducibleForASeed) {
  const Pointshell flat = sphere_samples(3000);
  NestedLevelOptions options;
  options.seed = 4;
  const Pointshell a = nested_pointshell(flat, options);
  const Pointshell b = nested_pointshell(flat, options);
  EXPECT_EQ(a.points, b.points);
  EXPECT_EQ(a.normals, b.normals);
  options.seed = 5;
  const Pointshell c = nested_pointshell(flat, options);
  EXPECT_NE(a.points.row(0), c.points.row(0));
  EXPECT_EQ(a.level_ends, c.level_ends);
}

TEST(NestedPointshell, RejectsInvalidInput) {
  Pointshell flat = sphere_samples(100);
  NestedLevelOptions options;
  options.schedule.growth = 1;
  EXPECT_THROW(nested_pointshell(flat, options), Error);
  flat.normals(3, 0) += 0.5;
  EXPECT_THROW(nested_pointshell(flat), Error);
}

}  // namespace
}  // namespace khz::contact
