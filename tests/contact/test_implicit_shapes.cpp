#include <khz/contact/common.hpp>
#include <khz/contact/field/distance_field.hpp>
#include <khz/contact/field/implicit_primitives.hpp>
#include <khz/contact/field/implicit_shapes.hpp>
#include <khz/test/allocation_probe.hpp>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <limits>
#include <numbers>
#include <random>
#include <vector>

namespace khz::contact {
namespace {

static_assert(DistanceField<HalfSpace>);
static_assert(DistanceField<ConvexPolytope>);
static_assert(DistanceField<Sphere>);
static_assert(DistanceField<Box>);
static_assert(DistanceField<Cylinder>);
static_assert(DistanceField<ImplicitShape>);
static_assert(DistanceField<ImplicitUnion>);

constexpr double kInfinity = std::numeric_limits<double>::infinity();

Eigen::Vector3d random_point(std::mt19937& random, double half_edge) {
  std::uniform_real_distribution<double> uniform(-half_edge, half_edge);
  return {uniform(random), uniform(random), uniform(random)};
}

Eigen::Quaterniond random_rotation(std::mt19937& random) {
  std::normal_distribution<double> normal;
  return Eigen::Quaterniond(normal(random), normal(random), normal(random), normal(random))
      .normalized();
}

// ---- Brute-force references: nearest points on the boundary's pieces, found separately ----

Eigen::Vector3d closest_on_segment(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                   const Eigen::Vector3d& b) {
  const double t = std::clamp((p - a).dot(b - a) / (b - a).squaredNorm(), 0.0, 1.0);
  return a + t * (b - a);
}

/// Distance from p to the triangle abc: its plane's foot if that lies inside, else the nearest
/// of the three edges.
double triangle_distance(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                         const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  const Eigen::Vector3d n = (b - a).cross(c - a).normalized();
  const Eigen::Vector3d foot = p - n.dot(p - a) * n;
  const bool inside = (b - a).cross(foot - a).dot(n) >= 0 && (c - b).cross(foot - b).dot(n) >= 0 &&
                      (a - c).cross(foot - c).dot(n) >= 0;
  if (inside) return (p - foot).norm();
  return std::min({(p - closest_on_segment(p, a, b)).norm(),
                   (p - closest_on_segment(p, b, c)).norm(),
                   (p - closest_on_segment(p, c, a)).norm()});
}

/// Distance from p to the parallelogram corner + s·u + t·v, (s, t) ∈ [0, 1]².
double parallelogram_distance(const Eigen::Vector3d& p, const Eigen::Vector3d& corner,
                              const Eigen::Vector3d& u, const Eigen::Vector3d& v) {
  return std::min(triangle_distance(p, corner, corner + u, corner + u + v),
                  triangle_distance(p, corner, corner + u + v, corner + v));
}

/// A box as its 8 corners in the world: body corner (±a, ±b, ±c) moved by `pose`.
struct WorldBox {
  std::array<Eigen::Vector3d, 8> corners;  // index bits: x, y, z sign (0 = −, 1 = +)
  Eigen::Isometry3d pose;
  Eigen::Vector3d half;

  WorldBox(const Eigen::Vector3d& half_extents, const Eigen::Isometry3d& placement)
      : pose(placement), half(half_extents) {
    for (int c = 0; c < 8; ++c) {
      const Eigen::Vector3d body((c & 1) ? half.x() : -half.x(), (c & 2) ? half.y() : -half.y(),
                                 (c & 4) ? half.z() : -half.z());
      corners[static_cast<std::size_t>(c)] = pose * body;
    }
  }
  /// Signed distance by brute force: the least distance to the six face rectangles, negative
  /// if p is behind all six face planes.
  double distance(const Eigen::Vector3d& p) const {
    double least = kInfinity;
    bool inside = true;
    for (int axis = 0; axis < 3; ++axis) {
      const int u = 1 << ((axis + 1) % 3), v = 1 << ((axis + 2) % 3);
      for (int side = 0; side < 2; ++side) {
        const int base = side << axis;
        const Eigen::Vector3d& o = corners[static_cast<std::size_t>(base)];
        least = std::min(
            least, parallelogram_distance(p, o, corners[base | u] - o, corners[base | v] - o));
        // Outward normal of this face.
        const Eigen::Vector3d outward = (side == 0 ? -1.0 : 1.0) * pose.linear().col(axis);
        if (outward.dot(p - o) > 0.0) inside = false;
      }
    }
    return inside ? -least : least;
  }
};

/// Signed distance to the capped cylinder by brute force: the least of the distances to the
/// mantle (nearest point at the clamped height, on the circle) and to the two cap disks
/// (foot on the cap plane, pulled into the disk).
double cylinder_reference(const Eigen::Vector3d& p, const Eigen::Vector3d& cap0,
                          const Eigen::Vector3d& cap1, double radius) {
  const Eigen::Vector3d axis = (cap1 - cap0).normalized();
  const double length = (cap1 - cap0).norm();
  const double height = (p - cap0).dot(axis);
  const Eigen::Vector3d radial = (p - cap0) - height * axis;
  const double rho = radial.norm();
  const Eigen::Vector3d direction = radial / rho;  // test points are never on the axis
  const Eigen::Vector3d mantle = cap0 + std::clamp(height, 0.0, length) * axis + radius * direction;
  double least = (p - mantle).norm();
  for (const Eigen::Vector3d& cap : {cap0, cap1}) {
    const Eigen::Vector3d foot = cap + std::min(rho, radius) * direction;
    least = std::min(least, (p - foot).norm());
  }
  const bool inside = rho <= radius && height >= 0.0 && height <= length;
  return inside ? -least : least;
}

/// Central-difference gradient of `f`.
Eigen::Vector3d numerical_gradient(const std::function<double(const Eigen::Vector3d&)>& f,
                                   const Eigen::Vector3d& p) {
  const double h = 1e-6;
  Eigen::Vector3d g;
  for (int axis = 0; axis < 3; ++axis) {
    const Eigen::Vector3d step = h * Eigen::Vector3d::Unit(axis);
    g[axis] = (f(p + step) - f(p - step)) / (2 * h);
  }
  return g;
}

/// distance_and_gradient() returns distance() and, where `smooth(p)`, the finite-difference
/// gradient of distance(), of unit length.
template <typename Field>
void expect_consistent_gradient(const Field& field, const Eigen::Vector3d& p) {
  Eigen::Vector3d gradient;
  const double d = field.distance_and_gradient(p, gradient);
  EXPECT_EQ(d, field.distance(p));
  EXPECT_NEAR(gradient.norm(), 1.0, 1e-12);
  const Eigen::Vector3d numerical =
      numerical_gradient([&](const Eigen::Vector3d& q) { return field.distance(q); }, p);
  // Central differences of a smooth function with step 1e-6: error ~1e-9 plus rounding ~1e-10.
  EXPECT_LT((gradient - numerical).norm(), 1e-6) << "at " << p.transpose();
}

TEST(ImplicitPrimitives, SphereIsExactWithUnitGradients) {
  const Sphere sphere(Eigen::Vector3d(0.1, -0.2, 0.3), 0.7);
  std::mt19937 random(1);
  for (int trial = 0; trial < 1000; ++trial) {
    const Eigen::Vector3d p = random_point(random, 2.0);
    const double r = (p - sphere.center()).norm();
    EXPECT_NEAR(sphere.distance(p), r - 0.7, 1e-15);
    if (r > 1e-3) expect_consistent_gradient(sphere, p);
  }
  Eigen::Vector3d gradient;
  EXPECT_EQ(sphere.distance_and_gradient(sphere.center(), gradient), -0.7);
  EXPECT_EQ(gradient, Eigen::Vector3d::UnitX());
}

TEST(ImplicitPrimitives, HalfSpaceAndSlabAreExactEverywhere) {
  const HalfSpace plane = HalfSpace::through(Eigen::Vector3d(0, 0, 0.5), Eigen::Vector3d(0, 0, 2));
  EXPECT_EQ(plane.normal(), Eigen::Vector3d::UnitZ());
  EXPECT_DOUBLE_EQ(plane.offset(), 0.5);
  const Eigen::Vector3d n = Eigen::Vector3d(1, 2, -2) / 3.0;
  const ConvexPolytope slab = ConvexPolytope::slab(3.0 * n, -0.2, 0.4);
  std::mt19937 random(2);
  for (int trial = 0; trial < 1000; ++trial) {
    const Eigen::Vector3d p = random_point(random, 2.0);
    EXPECT_NEAR(plane.distance(p), p.z() - 0.5, 1e-15);
    // Distance to the slab {−0.2 ≤ n·p ≤ 0.4}: to the nearer plane, signed.
    const double s = n.dot(p);
    const double reference = s > 0.4 ? s - 0.4 : s < -0.2 ? -0.2 - s : -std::min(s + 0.2, 0.4 - s);
    EXPECT_NEAR(slab.distance(p), reference, 1e-15);
    if (std::abs(s - 0.1) > 1e-4) expect_consistent_gradient(slab, p);  // 0.1: the mid-plane
    expect_consistent_gradient(plane, p);
  }
}

TEST(ImplicitPrimitives, ConvexPolytopeIsExactInsideAndALowerBoundOutside) {
  // A tetrahedron as four half-spaces; the reference is the least distance to its faces.
  const std::array<Eigen::Vector3d, 4> v = {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 0, 0),
                                            Eigen::Vector3d(0.2, 0.9, 0),
                                            Eigen::Vector3d(0.3, 0.3, 0.8)};
  const int faces[4][3] = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}};  // outward
  std::vector<HalfSpace> half_spaces;
  for (const auto& f : faces) {
    const Eigen::Vector3d normal = (v[f[1]] - v[f[0]]).cross(v[f[2]] - v[f[0]]);
    half_spaces.push_back(HalfSpace::through(v[f[0]], normal));
  }
  const ConvexPolytope tetrahedron(half_spaces);
  std::mt19937 random(3);
  int inside = 0, outside_strict = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    const Eigen::Vector3d p = Eigen::Vector3d(0.4, 0.3, 0.2) + random_point(random, 0.6);
    double reference = kInfinity;
    for (const auto& f : faces) {
      reference = std::min(reference, triangle_distance(p, v[f[0]], v[f[1]], v[f[2]]));
    }
    const double d = tetrahedron.distance(p);
    if (d < 0.0) {
      ++inside;
      EXPECT_NEAR(d, -reference, 1e-14);
    } else {
      EXPECT_LE(d, reference + 1e-14);  // conservative
      if (d < reference - 1e-3) ++outside_strict;
    }
    // Away from the planes' switching surfaces the gradient is the maximizing plane's normal.
    std::array<double, 4> distances{};
    for (std::size_t i = 0; i < 4; ++i) distances[i] = half_spaces[i].distance(p);
    std::sort(distances.begin(), distances.end());
    if (distances[3] - distances[2] > 1e-4) expect_consistent_gradient(tetrahedron, p);
  }
  EXPECT_GT(inside, 100);
  EXPECT_GT(outside_strict, 100);  // beyond edges and corners it is not the distance
}

TEST(ImplicitPrimitives, BoxIsExactInsideAndOutside) {
  const Eigen::Vector3d half(0.5, 0.3, 0.8);
  const Box box(Eigen::Vector3d(0.2, 0.1, -0.1), half);
  const WorldBox reference(half, Eigen::Isometry3d(Eigen::Translation3d(0.2, 0.1, -0.1)));
  std::mt19937 random(4);
  for (int trial = 0; trial < 3000; ++trial) {
    const Eigen::Vector3d p = random_point(random, 1.5);
    EXPECT_NEAR(box.distance(p), reference.distance(p), 1e-14) << p.transpose();
    // Inside, the gradient jumps where two faces are equally near.
    const Eigen::Vector3d q = (p - box.center()).cwiseAbs() - half;
    std::array<double, 3> sorted = {q.x(), q.y(), q.z()};
    std::sort(sorted.begin(), sorted.end());
    if (sorted[2] > 1e-4 || sorted[2] - sorted[1] > 1e-4) expect_consistent_gradient(box, p);
  }
}

TEST(ImplicitPrimitives, CylinderIsExactInsideAndOutside) {
  const Eigen::Vector3d cap0(0.1, -0.3, 0.2), cap1(-0.4, 0.5, 0.6);
  const double radius = 0.35;
  const Cylinder cylinder(cap0, cap1, radius);
  EXPECT_NEAR(cylinder.half_length(), 0.5 * (cap1 - cap0).norm(), 1e-15);
  std::mt19937 random(5);
  int inside = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    const Eigen::Vector3d p = Eigen::Vector3d(-0.15, 0.1, 0.4) + random_point(random, 0.9);
    const double reference = cylinder_reference(p, cap0, cap1, radius);
    const double d = cylinder.distance(p);
    EXPECT_NEAR(d, reference, 1e-14) << p.transpose();
    inside += d < 0.0 ? 1 : 0;
    // Smooth except on the axis and, inside, where mantle and cap are equally near.
    const double z = cylinder.axis().dot(p - cylinder.center());
    const double rho = ((p - cylinder.center()) - z * cylinder.axis()).norm();
    const double q_radial = rho - radius, q_axial = std::abs(z) - cylinder.half_length();
    if (rho > 1e-3 && (d > 1e-4 || std::abs(q_radial - q_axial) > 1e-4)) {
      expect_consistent_gradient(cylinder, p);
    }
  }
  EXPECT_GT(inside, 100);
  // On the axis inside, nearest to the mantle: any radial direction, perpendicular to the axis.
  Eigen::Vector3d gradient;
  EXPECT_NEAR(cylinder.distance_and_gradient(cylinder.center(), gradient), -radius, 1e-15);
  EXPECT_NEAR(gradient.norm(), 1.0, 1e-15);
  EXPECT_NEAR(gradient.dot(cylinder.axis()), 0.0, 1e-15);
}

TEST(ImplicitShape, RigidPlacementMovesTheExactDistance) {
  std::mt19937 random(6);
  const Eigen::Vector3d half(0.4, 0.2, 0.6);
  for (int pose_trial = 0; pose_trial < 5; ++pose_trial) {
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.linear() = random_rotation(random).toRotationMatrix();
    pose.translation() = random_point(random, 0.5);
    const ImplicitShape box(Box(Eigen::Vector3d::Zero(), half), pose);
    const WorldBox reference(half, pose);
    EXPECT_TRUE(box.pose().isApprox(pose, 1e-15));
    for (int trial = 0; trial < 500; ++trial) {
      const Eigen::Vector3d p = random_point(random, 1.5);
      EXPECT_NEAR(box.distance(p), reference.distance(p), 1e-13);
      const Eigen::Vector3d q = (pose.inverse() * p).cwiseAbs() - half;
      std::array<double, 3> sorted = {q.x(), q.y(), q.z()};
      std::sort(sorted.begin(), sorted.end());
      if (sorted[2] > 1e-4 || sorted[2] - sorted[1] > 1e-4) expect_consistent_gradient(box, p);
    }
    // A cylinder along z placed by the pose equals the cylinder between the moved caps.
    const ImplicitShape placed(
        Cylinder(Eigen::Vector3d(0, 0, -0.3), Eigen::Vector3d(0, 0, 0.5), 0.2), pose);
    const Cylinder moved(pose * Eigen::Vector3d(0, 0, -0.3), pose * Eigen::Vector3d(0, 0, 0.5),
                         0.2);
    for (int trial = 0; trial < 200; ++trial) {
      const Eigen::Vector3d p = random_point(random, 1.0);
      EXPECT_NEAR(placed.distance(p), moved.distance(p), 1e-13);
    }
  }
}

TEST(ImplicitUnion, IsTheMinimumOfItsShapesWithTheMinimizersGradient) {
  std::vector<ImplicitShape> shapes = {
      Sphere(Eigen::Vector3d(-0.5, 0, 0), 0.4),
      Box(Eigen::Vector3d(0.4, 0.1, 0), Eigen::Vector3d(0.3, 0.3, 0.2)),
      Cylinder(Eigen::Vector3d(0, -0.6, -0.5), Eigen::Vector3d(0, -0.6, 0.5), 0.15),
      HalfSpace(Eigen::Vector3d(0, 0, 1), -0.8),  // a floor
      ConvexPolytope::slab(Eigen::Vector3d(1, 1, 0), 1.0, 1.2)};
  const std::vector<ImplicitShape> parts = shapes;
  const ImplicitUnion scene(std::move(shapes));
  ASSERT_EQ(scene.shapes().size(), 5u);
  std::mt19937 random(7);
  for (int trial = 0; trial < 2000; ++trial) {
    const Eigen::Vector3d p = random_point(random, 1.5);
    std::vector<double> distances;
    for (const ImplicitShape& part : parts) distances.push_back(part.distance(p));
    const auto least = std::min_element(distances.begin(), distances.end());
    EXPECT_EQ(scene.distance(p), *least);
    Eigen::Vector3d gradient, expected;
    EXPECT_EQ(scene.distance_and_gradient(p, gradient), *least);
    parts[static_cast<std::size_t>(least - distances.begin())].distance_and_gradient(p, expected);
    EXPECT_EQ(gradient, expected);
  }
}

TEST(ImplicitUnion, QueriesAllocateNothing) {
  const ImplicitUnion scene({Sphere(Eigen::Vector3d::Zero(), 0.5),
                             ConvexPolytope::slab(Eigen::Vector3d::UnitX(), -0.1, 0.1),
                             ImplicitShape(Box(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones()),
                                           Eigen::Isometry3d(Eigen::Translation3d(2, 0, 0)))});
  std::mt19937 random(8);
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < 100; ++i) points.push_back(random_point(random, 3.0));
  double sum = 0.0;
  Eigen::Vector3d gradient;
  test::allocation_count = 0;
  for (const Eigen::Vector3d& p : points)
    sum += scene.distance(p) + scene.distance_and_gradient(p, gradient);
  EXPECT_EQ(test::allocation_count.load(), 0u);
  EXPECT_TRUE(std::isfinite(sum));
}

TEST(ImplicitShapes, InvalidParametersThrow) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const Eigen::Vector3d zero = Eigen::Vector3d::Zero(), x = Eigen::Vector3d::UnitX();
  EXPECT_THROW(HalfSpace(zero, 0.0), Error);
  EXPECT_THROW(HalfSpace(Eigen::Vector3d(nan, 0, 1), 0.0), Error);
  EXPECT_THROW(HalfSpace(x, kInfinity), Error);
  EXPECT_THROW(HalfSpace::through(Eigen::Vector3d(nan, 0, 0), x), Error);
  EXPECT_THROW(ConvexPolytope({}), Error);
  EXPECT_THROW(ConvexPolytope::slab(x, 0.5, 0.5), Error);
  EXPECT_THROW(ConvexPolytope::slab(zero, 0.0, 1.0), Error);
  EXPECT_THROW(Sphere(zero, 0.0), Error);
  EXPECT_THROW(Sphere(zero, -1.0), Error);
  EXPECT_THROW(Sphere(zero, nan), Error);
  EXPECT_THROW(Sphere(Eigen::Vector3d(0, kInfinity, 0), 1.0), Error);
  EXPECT_THROW(Box(zero, Eigen::Vector3d(1, 0, 1)), Error);
  EXPECT_THROW(Box(zero, Eigen::Vector3d(1, 1, -1)), Error);
  EXPECT_THROW(Box(Eigen::Vector3d(nan, 0, 0), Eigen::Vector3d::Ones()), Error);
  EXPECT_THROW(Cylinder(zero, zero, 1.0), Error);
  EXPECT_THROW(Cylinder(zero, x, 0.0), Error);
  EXPECT_THROW(Cylinder(zero, Eigen::Vector3d(nan, 0, 0), 1.0), Error);
  EXPECT_THROW(ImplicitUnion({}), Error);
  const Sphere sphere(zero, 1.0);
  Eigen::Isometry3d scaled = Eigen::Isometry3d::Identity();
  scaled.linear() *= 1.01;
  EXPECT_THROW(ImplicitShape(sphere, scaled), Error);
  Eigen::Isometry3d mirrored = Eigen::Isometry3d::Identity();
  mirrored.linear()(0, 0) = -1.0;
  EXPECT_THROW(ImplicitShape(sphere, mirrored), Error);
  Eigen::Isometry3d shifted = Eigen::Isometry3d::Identity();
  shifted.translation().x() = nan;
  EXPECT_THROW(ImplicitShape(sphere, shifted), Error);
}

}  // namespace
}  // namespace khz::contact
