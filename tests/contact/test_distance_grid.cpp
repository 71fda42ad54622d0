#include <khz/contact/common.hpp>
#include <khz/contact/field/distance_field.hpp>
#include <khz/contact/field/distance_grid.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <random>

namespace khz::contact {
namespace {

static_assert(DistanceField<DistanceGrid>);

/// A grid sampling `f` at its nodes.
DistanceGrid sampled(const GridGeometry& geometry,
                     const std::function<double(Eigen::Vector3d)>& f) {
  std::vector<float> values(static_cast<std::size_t>(geometry.node_count()));
  for (int k = 0; k <= geometry.cells; ++k) {
    for (int j = 0; j <= geometry.cells; ++j) {
      for (int i = 0; i <= geometry.cells; ++i) {
        values[static_cast<std::size_t>(geometry.node_index(i, j, k))] =
            static_cast<float>(f(geometry.node_position(i, j, k)));
      }
    }
  }
  return DistanceGrid(geometry, std::move(values), true);
}

GridGeometry unit_cube(int cells) { return {Eigen::Vector3d(-1, -1, -1), 2.0 / cells, cells}; }

Eigen::Vector3d random_point(std::mt19937& random, double half_edge) {
  std::uniform_real_distribution<double> uniform(-half_edge, half_edge);
  return {uniform(random), uniform(random), uniform(random)};
}

TEST(DistanceGrid, ReproducesAPlaneExactlyWithItsGradient) {
  // Trilinear interpolation is exact for affine functions: the signed distance to a plane.
  const Eigen::Vector3d normal = Eigen::Vector3d(1, -2, 0.5).normalized();
  const DistanceGrid grid =
      sampled(unit_cube(16), [&](const Eigen::Vector3d& p) { return normal.dot(p) - 0.1; });
  std::mt19937 random(1);
  for (int trial = 0; trial < 1000; ++trial) {
    const Eigen::Vector3d p = random_point(random, 1.0);
    Eigen::Vector3d gradient;
    const double d = grid.distance_and_gradient(p, gradient);
    EXPECT_NEAR(d, normal.dot(p) - 0.1, 1e-6);  // float node values
    EXPECT_LT((gradient - normal).norm(), 1e-5);
    EXPECT_EQ(grid.distance(p), d);
  }
}

TEST(DistanceGrid, GradientIsTheDerivativeOfTheInterpolant) {
  const DistanceGrid grid =
      sampled(unit_cube(8), [](const Eigen::Vector3d& p) { return p.norm() - 0.6; });
  std::mt19937 random(2);
  const double h = 1e-6;
  for (int trial = 0; trial < 200; ++trial) {
    const Eigen::Vector3d p = random_point(random, 0.95);
    Eigen::Vector3d gradient;
    grid.distance_and_gradient(p, gradient);
    for (int axis = 0; axis < 3; ++axis) {
      const Eigen::Vector3d step = h * Eigen::Vector3d::Unit(axis);
      const double difference = (grid.distance(p + step) - grid.distance(p - step)) / (2 * h);
      // A central difference can straddle a cell face, where the gradient jumps by O(h·curvature).
      EXPECT_NEAR(gradient[axis], difference, 2e-3) << "axis " << axis;
    }
  }
}

TEST(DistanceGrid, InterpolatesASphereToSecondOrder) {
  // The interpolation error of a smooth field falls by ~4 when the spacing halves.
  const auto sphere = [](const Eigen::Vector3d& p) { return p.norm() - 0.6; };
  double errors[2];
  for (int refinement = 0; refinement < 2; ++refinement) {
    const DistanceGrid grid = sampled(unit_cube(16 << refinement), sphere);
    std::mt19937 random(3);
    errors[refinement] = 0;
    for (int trial = 0; trial < 2000; ++trial) {
      Eigen::Vector3d p = random_point(random, 1.0);
      if (p.norm() < 0.3) continue;  // the cone tip at the centre is not smooth
      errors[refinement] = std::max(errors[refinement], std::abs(grid.distance(p) - sphere(p)));
    }
  }
  EXPECT_GT(errors[0] / errors[1], 3.0) << errors[0] << " then " << errors[1];
}

TEST(DistanceGrid, OutsideTheBoxTheBoundOfInequality314IsConservative) {
  const auto sphere = [](const Eigen::Vector3d& p) { return p.norm() - 0.6; };
  const DistanceGrid grid = sampled(unit_cube(10), sphere);
  // Boundary nodes are at least 0.4 from the sphere; the bound subtracts h/√2.
  EXPECT_NEAR(grid.boundary_minimum(), 0.4 - 0.2 / std::sqrt(2.0), 1e-6);
  std::mt19937 random(4);
  for (int trial = 0; trial < 1000; ++trial) {
    const Eigen::Vector3d p = random_point(random, 10.0);
    if (grid.geometry().box().contains(p)) continue;
    Eigen::Vector3d gradient;
    const double bound = grid.distance_and_gradient(p, gradient);
    EXPECT_LE(bound, sphere(p) + 1e-12);
    // The bound grows with the distance to the box, along its gradient.
    const double to_box = grid.geometry().box().exteriorDistance(p);
    EXPECT_NEAR(bound, to_box + grid.boundary_minimum(), 1e-12);
    EXPECT_NEAR(gradient.norm(), 1.0, 1e-12);
    EXPECT_NEAR(grid.distance(p + 1e-3 * gradient) - bound, 1e-3, 1e-9);
  }
}

TEST(DistanceGrid, TheBoxSurfaceBelongsToTheInside) {
  const DistanceGrid grid =
      sampled(unit_cube(4), [](const Eigen::Vector3d& p) { return p.x() + 2 * p.y() + 3 * p.z(); });
  EXPECT_NEAR(grid.distance(Eigen::Vector3d(1, 1, 1)), 6.0, 1e-6);      // the last node
  EXPECT_NEAR(grid.distance(Eigen::Vector3d(-1, 1, 0)), 1.0, 1e-6);     // on two faces
  EXPECT_NEAR(grid.distance(Eigen::Vector3d(-1, -1, -1)), -6.0, 1e-6);  // the origin node
}

TEST(DistanceGrid, RejectsInconsistentInput) {
  const GridGeometry geometry = unit_cube(2);
  EXPECT_THROW(DistanceGrid(geometry, std::vector<float>(26, 0.0f), true), Error);
  std::vector<float> values(27, 0.0f);
  values[13] = std::numeric_limits<float>::quiet_NaN();
  EXPECT_THROW(DistanceGrid(geometry, values, true), Error);
  GridGeometry flat = geometry;
  flat.spacing = 0.0;
  EXPECT_THROW(DistanceGrid(flat, std::vector<float>(27, 0.0f), true), Error);
}

TEST(GridGeometry, CubeAroundCentresAndExpandsTheLongestSide) {
  const Eigen::AlignedBox3d bounds(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(2, 1, 0.5));
  const GridGeometry g = GridGeometry::cube_around(bounds, 1.5, 30);
  EXPECT_DOUBLE_EQ(g.size(), 3.0);
  EXPECT_DOUBLE_EQ(g.spacing, 0.1);
  EXPECT_LT((g.box().center() - bounds.center()).norm(), 1e-12);
  EXPECT_TRUE(g.box().contains(bounds));
  EXPECT_THROW(GridGeometry::cube_around(bounds, 0.9, 30), Error);
  EXPECT_THROW(GridGeometry::cube_around(bounds, 1.5, 0), Error);
  EXPECT_THROW(GridGeometry::cube_around(Eigen::AlignedBox3d(), 1.5, 8), Error);
}

}  // namespace
}  // namespace khz::contact
