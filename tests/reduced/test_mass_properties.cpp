// Mass properties of closed meshes against closed forms: a box (exact), a turned box far from the
// origin (the tensor turns, R I Rᵀ, and no digits are lost), a fine sphere (2/5 m r², to the
// tessellation's error); what bounds no solid is refused.
#include <khz/reduced/errors.hpp>
#include <khz/reduced/mesh/mass_properties.hpp>
#include <khz/test/fixtures.hpp>
#include <khz/test/generated_meshes.hpp>

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>
#include <numbers>

namespace khz::reduced {
namespace {

/// An a × b × c box [0, a] × [0, b] × [0, c], outward triangles.
TriangleMesh box(double a, double b, double c) {
  TriangleMesh mesh = test::unit_cube_surface();
  mesh.vertices = mesh.vertices * Eigen::Vector3d(a, b, c).asDiagonal();
  return mesh;
}

TEST(MassProperties, BoxIsExact) {
  const double a = 0.3, b = 0.2, c = 0.1, density = 800.0;
  const MassProperties p = mass_properties(box(a, b, c), density);
  const double m = density * a * b * c;
  EXPECT_NEAR(p.volume, a * b * c, 1e-15);
  EXPECT_NEAR(p.mass, m, 1e-12);
  EXPECT_LT((p.centre - Eigen::Vector3d(a, b, c) / 2).norm(), 1e-15);
  const Eigen::Matrix3d expected =
      Eigen::Vector3d(b * b + c * c, a * a + c * c, a * a + b * b).asDiagonal() * (m / 12.0);
  EXPECT_LT((p.inertia - expected).norm(), 1e-14 * expected.norm()) << p.inertia;
}

TEST(MassProperties, TurnedAndMovedBoxTurnsTheTensor) {
  const double density = 1000.0;
  const TriangleMesh still = box(0.3, 0.2, 0.1);
  TriangleMesh moved = still;
  const Eigen::Matrix3d rotation =
      Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  const Eigen::Vector3d offset(50.0, -20.0, 7.0);  // far from the origin
  for (Eigen::Index v = 0; v < moved.num_vertices(); ++v) {
    moved.vertices.row(v) = (rotation * still.vertices.row(v).transpose() + offset).transpose();
  }
  const MassProperties a = mass_properties(still, density);
  const MassProperties b = mass_properties(moved, density);
  EXPECT_NEAR(b.mass, a.mass, 1e-12 * a.mass);
  EXPECT_LT((b.centre - (rotation * a.centre + offset)).norm(), 1e-12);
  const Eigen::Matrix3d turned = rotation * a.inertia * rotation.transpose();
  EXPECT_LT((b.inertia - turned).norm(), 1e-10 * a.inertia.norm());
}

TEST(MassProperties, FineSphereMatchesTheClosedForm) {
  const double radius = 0.05, density = 7800.0;
  TriangleMesh sphere = test::uv_sphere(256, 128);
  sphere.vertices *= radius;
  const MassProperties p = mass_properties(sphere, density);
  // The inscribed polyhedron's volume falls short by the tessellation error; the inertia of a
  // solid sphere of that same volume, 2/5 m r_v², agrees to higher order.
  const double exact_volume = 4.0 / 3.0 * std::numbers::pi * std::pow(radius, 3);
  EXPECT_NEAR(p.volume, exact_volume, 2e-3 * exact_volume);
  const double r_v = std::cbrt(3.0 * p.volume / (4.0 * std::numbers::pi));
  const double expected = 0.4 * p.mass * r_v * r_v;
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(p.inertia(k, k), expected, 2e-3 * expected);
  EXPECT_LT(std::abs(p.inertia(0, 1)) + std::abs(p.inertia(1, 2)) + std::abs(p.inertia(0, 2)),
            1e-3 * expected);
  EXPECT_LT(p.centre.norm(), 1e-6 * radius);
}

TEST(MassProperties, RefusesWhatBoundsNoSolid) {
  TriangleMesh inside_out = box(1, 1, 1);
  inside_out.triangles.col(1).swap(inside_out.triangles.col(2));
  EXPECT_TRUE(test::throws_with_message<MeshError>(
      [&] { mass_properties(inside_out, 1000.0); },
      "the mesh encloses no positive volume (signed volume -1.000000)"));
  EXPECT_TRUE(test::throws_with_message<MeshError>([&] { mass_properties(TriangleMesh{}, 1.0); },
                                                   "encloses no positive volume"));
  EXPECT_TRUE(test::throws_with_message<Error>([&] { mass_properties(box(1, 1, 1), 0.0); },
                                               "the density must be finite and > 0 (kg/m³)"));
  TriangleMesh broken = box(1, 1, 1);
  broken.triangles(0, 0) = 99;
  EXPECT_THROW(mass_properties(broken, 1.0), MeshError);
}

}  // namespace
}  // namespace khz::reduced
