#include <khz/contact/common.hpp>
#include <khz/contact/field/mesh_distance.hpp>
#include <khz/reduced/io/mesh_file.hpp>
#include <khz/test/fixtures.hpp>
#include <khz/test/generated_meshes.hpp>

#include "mesh_distance_reference.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

namespace khz::contact {
namespace {

using test::brute_force_distance;
using test::corner;
using test::triangle_distance;

struct NamedMesh {
  std::string name;
  TriangleMesh mesh;
};

/// The icosphere with its twelve five-fold vertices moved to `scale` times the radius: sharp
/// spikes (scale > 1) or pits (scale < 1), where the normal cone of a vertex is wider than any
/// one face normal can represent.
TriangleMesh star(double scale) {
  TriangleMesh mesh = test::icosphere(1);
  mesh.vertices.topRows(12) *= scale;
  return mesh;
}

/// Closed, consistently oriented meshes with convex, concave and saddle edges and vertices.
std::vector<NamedMesh> closed_meshes() {
  return {{"cube", test::unit_cube_surface()}, {"uv_sphere", test::uv_sphere(16, 9)},
          {"icosphere", test::icosphere(2)},   {"torus", test::torus(1.0, 0.35, 24, 12)},
          {"spiky star", star(3.0)},           {"pitted star", star(0.3)}};
}

double diagonal(const TriangleMesh& mesh) {
  return (mesh.vertices.colwise().maxCoeff() - mesh.vertices.colwise().minCoeff()).norm();
}

Eigen::Vector3d random_unit(std::mt19937& random) {
  std::normal_distribution<double> normal;
  return Eigen::Vector3d(normal(random), normal(random), normal(random)).normalized();
}

/// Query points for `mesh`: uniform in twice its bounding box, and near its vertices and edge
/// points at distances from 1e-9 to 1e-2 of its diagonal, where features meet.
std::vector<Eigen::Vector3d> query_points(const TriangleMesh& mesh, std::mt19937& random,
                                          int uniform_count, int near_count) {
  const Eigen::Vector3d low = mesh.vertices.colwise().minCoeff();
  const Eigen::Vector3d high = mesh.vertices.colwise().maxCoeff();
  const Eigen::Vector3d centre = 0.5 * (low + high);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::vector<Eigen::Vector3d> points;
  for (int s = 0; s < uniform_count; ++s) {
    const Eigen::Vector3d offset(unit(random), unit(random), unit(random));
    points.push_back(centre + offset.cwiseProduct(high - low));
  }
  const double size = diagonal(mesh);
  std::uniform_int_distribution<Eigen::Index> triangle(0, mesh.num_triangles() - 1);
  std::uniform_int_distribution<int> exponent(2, 9);
  std::uniform_real_distribution<double> along(0.0, 1.0);
  for (int s = 0; s < near_count; ++s) {
    const Eigen::Index t = triangle(random);
    const int k = s % 3;
    // Alternately a vertex and a point on an edge.
    const Eigen::Vector3d base =
        s % 2 == 0 ? corner(mesh, t, k)
                   : corner(mesh, t, k) +
                         along(random) * (corner(mesh, t, (k + 1) % 3) - corner(mesh, t, k));
    points.push_back(base + size * std::pow(10.0, -exponent(random)) * random_unit(random));
  }
  return points;
}

TEST(MeshDistance, MatchesBruteForceOnGeneratedMeshes) {
  std::vector<NamedMesh> meshes = closed_meshes();
  meshes.push_back({"open square", test::unit_square()});
  meshes.push_back({"soup", test::random_soup(60, 7)});
  std::mt19937 random(11);
  for (const auto& [name, mesh] : meshes) {
    SCOPED_TRACE(name);
    const MeshDistance distance(mesh);
    const double size = diagonal(mesh);
    for (const Eigen::Vector3d& p : query_points(mesh, random, 600, 1500)) {
      const ClosestPoint closest = distance.closest(p);
      ASSERT_GE(closest.triangle, 0);
      ASSERT_LT(closest.triangle, mesh.num_triangles());
      EXPECT_NEAR(closest.distance, brute_force_distance(mesh, p), 1e-13 * size);
      EXPECT_NEAR((p - closest.point).norm(), closest.distance, 1e-13 * size);
      // The point lies on the triangle it names.
      EXPECT_LT(triangle_distance(mesh, closest.triangle, closest.point), 1e-13 * size);
      EXPECT_NEAR(closest.pseudonormal.norm(), 1.0, 1e-12);
    }
  }
}

TEST(MeshDistance, MatchesBruteForceOnDino) {
  const TriangleMesh mesh = reduced::read_triangle_mesh(test::cgal_mesh("dino.off"));
  const MeshDistance distance(mesh);
  std::mt19937 random(12);
  const double size = diagonal(mesh);
  for (const Eigen::Vector3d& p : query_points(mesh, random, 150, 150)) {
    const ClosestPoint closest = distance.closest(p);
    EXPECT_NEAR(closest.distance, brute_force_distance(mesh, p), 1e-13 * size);
  }
}

TEST(MeshDistance, ReportsTheFeatureAndItsPseudonormal) {
  const MeshDistance cube(test::unit_cube_surface());
  struct Case {
    Eigen::Vector3d p;
    MeshFeature feature;
    Eigen::Vector3d point;
    Eigen::Vector3d pseudonormal;
  };
  const double r2 = std::sqrt(0.5), r3 = std::sqrt(1.0 / 3.0);
  const Case cases[] = {
      {{0.3, 0.2, 1.5}, MeshFeature::face, {0.3, 0.2, 1.0}, {0, 0, 1}},
      {{0.3, 0.2, 0.9}, MeshFeature::face, {0.3, 0.2, 1.0}, {0, 0, 1}},
      {{1.5, 0.4, 1.5}, MeshFeature::edge, {1.0, 0.4, 1.0}, {r2, 0, r2}},
      {{0.4, -1e-9, -2e-9}, MeshFeature::edge, {0.4, 0.0, 0.0}, {0, -r2, -r2}},
      {{1.5, 1.5, 1.5}, MeshFeature::vertex, {1, 1, 1}, {r3, r3, r3}},
      {{-1e-8, -2e-8, -3e-8}, MeshFeature::vertex, {0, 0, 0}, {-r3, -r3, -r3}},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(testing::Message() << "p = " << c.p.transpose());
    const ClosestPoint closest = cube.closest(c.p);
    EXPECT_EQ(closest.feature, c.feature);
    EXPECT_LT((closest.point - c.point).norm(), 1e-15);
    EXPECT_LT((closest.pseudonormal - c.pseudonormal).norm(), 1e-15);
  }
  // Over a face's diagonal the feature may be reported as that (flat) edge; the pseudonormal is
  // the face normal either way.
  EXPECT_LT((cube.closest({0.5, 0.5, 1.2}).pseudonormal - Eigen::Vector3d(0, 0, 1)).norm(), 1e-15);

  // The icosahedron's twelve vertices keep five-fold symmetry after subdivision: their
  // angle-weighted pseudonormals are radial.
  const TriangleMesh sphere = test::icosphere(2);
  const MeshDistance distance(sphere);
  for (Eigen::Index v = 0; v < 12; ++v) {
    const Eigen::Vector3d direction = sphere.vertices.row(v).transpose();
    const ClosestPoint closest = distance.closest(1.5 * direction);
    EXPECT_EQ(closest.feature, MeshFeature::vertex);
    EXPECT_LT((closest.pseudonormal - direction).norm(), 1e-12) << "vertex " << v;
  }
}

TEST(MeshDistance, SignMatchesTheWindingNumber) {
  std::mt19937 random(13);
  for (const auto& [name, mesh] : closed_meshes()) {
    SCOPED_TRACE(name);
    const MeshDistance distance(mesh);
    const double size = diagonal(mesh);
    std::vector<Eigen::Vector3d> points = query_points(mesh, random, 1000, 3000);
    // Every vertex's surroundings in all directions, where the vertex pseudonormal decides.
    for (Eigen::Index v = 0; v < mesh.num_vertices(); ++v) {
      for (int s = 0; s < 20; ++s) {
        points.push_back(mesh.vertices.row(v).transpose() +
                         (s % 2 == 0 ? 1e-2 : 1e-5) * size * random_unit(random));
      }
    }
    int checked = 0, errors = 0, inside = 0;
    for (const Eigen::Vector3d& p : points) {
      const ClosestPoint closest = distance.closest(p);
      if (closest.distance < 1e-12 * size) continue;  // on the surface: either side is right
      const bool is_inside = test::winding_number(mesh, p) > 0.5;
      ++checked;
      inside += is_inside;
      if ((closest.signed_distance(p) < 0.0) != is_inside) {
        ++errors;
        ADD_FAILURE() << "p = " << p.transpose() << ": signed distance "
                      << closest.signed_distance(p) << ", winding number "
                      << test::winding_number(mesh, p);
      }
    }
    EXPECT_EQ(errors, 0);
    EXPECT_GT(checked, 3500);
    EXPECT_GT(inside, 500);  // both sides are exercised
  }
}

TEST(MeshDistance, DegenerateTrianglesGiveFiniteAnswers) {
  // The cube with the edge from vertex 0 to 1 split at its midpoint by a zero-area triangle,
  // and a triangle repeating a vertex.
  TriangleMesh mesh = test::unit_cube_surface();
  mesh.vertices.conservativeResize(9, 3);
  mesh.vertices.row(8) << 0.5, 0.0, 0.0;
  mesh.triangles.conservativeResize(14, 3);
  mesh.triangles.row(12) << 0, 8, 1;
  mesh.triangles.row(13) << 3, 3, 7;
  const MeshDistance distance(mesh);
  std::mt19937 random(14);
  for (const Eigen::Vector3d& p : query_points(mesh, random, 500, 500)) {
    const ClosestPoint closest = distance.closest(p);
    EXPECT_NEAR(closest.distance, brute_force_distance(mesh, p), 1e-13);
    ASSERT_TRUE(closest.pseudonormal.allFinite());
    ASSERT_TRUE(closest.point.allFinite());
    if (closest.triangle >= 12) {
      EXPECT_NE(closest.feature, MeshFeature::face);
    }
  }
  // Near the split edge's midpoint the answer is still on the cube (sign outside).
  const Eigen::Vector3d p(0.5, -0.1, -0.1);
  EXPECT_GT(distance.closest(p).signed_distance(p), 0.0);
}

TEST(MeshDistance, RejectsInvalidMeshes) {
  TriangleMesh empty;
  EXPECT_TRUE(test::throws_with_message<MeshError>([&] { MeshDistance d(empty); }, "no triangles"));
  TriangleMesh bad_index = test::unit_cube_surface();
  bad_index.triangles(3, 1) = 8;
  EXPECT_THROW(MeshDistance d(bad_index), MeshError);
  TriangleMesh not_finite = test::unit_cube_surface();
  not_finite.vertices(2, 0) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(MeshDistance d(not_finite), MeshError);
}

TEST(MeshDistance, NonFinitePointsGiveNoTriangle) {
  const MeshDistance cube(test::unit_cube_surface());
  for (const double bad :
       {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()}) {
    const ClosestPoint closest = cube.closest({0.5, bad, 0.5});
    EXPECT_TRUE(std::isnan(closest.distance));
    EXPECT_EQ(closest.triangle, -1);
  }
}

TEST(MeshDistance, MovesKeepTheAnswers) {
  MeshDistance first(test::unit_cube_surface());
  MeshDistance second(std::move(first));
  EXPECT_DOUBLE_EQ(second.closest({2, 0.5, 0.5}).distance, 1.0);
  MeshDistance third(test::icosphere(1));
  third = std::move(second);
  EXPECT_DOUBLE_EQ(third.closest({2, 0.5, 0.5}).distance, 1.0);
}

}  // namespace
}  // namespace khz::contact
