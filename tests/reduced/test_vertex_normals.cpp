#include <khz/reduced/errors.hpp>
#include <khz/reduced/subspace/vertex_normals.hpp>
#include <khz/test/fixtures.hpp>
#include <khz/test/generated_meshes.hpp>

#include <gtest/gtest.h>

#include <Eigen/LU>

#include <cmath>

namespace khz::reduced {
namespace {

using test::throws_with_message;

VertexMatrix normals_of(const VertexMatrix& positions, const TriangleMatrix& triangles) {
  VertexMatrix normals(positions.rows(), 3);
  vertex_normals(positions, triangles, normals);
  return normals;
}

// Each cube corner has three triangle corners per face it touches, each adding its face normal
// times twice its area (1): vertex 0 touches one triangle of each of x=0, y=0, z=0; vertex 1 two
// of y=0 and z=0 and one of x=1.
TEST(VertexNormals, WeighFaceNormalsByArea) {
  const TriangleMesh cube = test::unit_cube_surface();
  const VertexMatrix normals = normals_of(cube.vertices, cube.triangles);
  EXPECT_LT((normals.row(0) - Eigen::RowVector3d(-1.0, -1.0, -1.0) / std::sqrt(3.0)).norm(), 1e-15);
  EXPECT_LT((normals.row(1) - Eigen::RowVector3d(1.0, -2.0, -2.0) / 3.0).norm(), 1e-15);
}

TEST(VertexNormals, PointOutwardOnAClosedMesh) {
  const TriangleMesh sphere = test::uv_sphere(32, 16);
  const VertexMatrix normals = normals_of(sphere.vertices, sphere.triangles);
  for (Eigen::Index v = 0; v < sphere.num_vertices(); ++v) {
    EXPECT_NEAR(normals.row(v).norm(), 1.0, 1e-15);
    // On the unit sphere the position is the normal, up to the faceting.
    EXPECT_GT(normals.row(v).dot(sphere.vertices.row(v)), 0.99) << "vertex " << v;
  }
}

// Cross products of edges map by cof(A) = det(A) A⁻ᵀ, so area-weighted normals of an affinely
// mapped mesh are A⁻ᵀ N normalized (det A > 0), shear included.
TEST(VertexNormals, TransformByTheInverseTransposeUnderAffineMaps) {
  const TriangleMesh sphere = test::uv_sphere(16, 9);
  Eigen::Matrix3d a;
  a << 1.2, 0.8, 0.1, -0.2, 0.9, 0.3, 0.1, -0.4, 1.5;
  ASSERT_GT(a.determinant(), 0.0);
  const VertexMatrix rest = normals_of(sphere.vertices, sphere.triangles);
  VertexMatrix mapped = sphere.vertices * a.transpose();
  mapped.rowwise() += Eigen::RowVector3d(0.3, -1.0, 2.0);
  const VertexMatrix normals = normals_of(mapped, sphere.triangles);
  const Eigen::Matrix3d inverse_transpose = a.inverse().transpose();
  for (Eigen::Index v = 0; v < sphere.num_vertices(); ++v) {
    const Eigen::Vector3d expected = (inverse_transpose * rest.row(v).transpose()).normalized();
    EXPECT_LT((normals.row(v).transpose() - expected).norm(), 1e-14)  // measured ≤ 1.2e-15
        << "vertex " << v;
  }
}

TEST(VertexNormals, UnusedVerticesGetZero) {
  TriangleMesh square = test::unit_square();
  square.vertices.conservativeResize(5, 3);
  square.vertices.row(4) << 3.0, 3.0, 3.0;
  const VertexMatrix normals = normals_of(square.vertices, square.triangles);
  EXPECT_EQ(normals.row(4), Eigen::RowVector3d::Zero());
  EXPECT_EQ(normals.row(0), Eigen::RowVector3d::UnitZ());
}

TEST(VertexNormals, RejectsWrongSizesAndIndices) {
  const TriangleMesh cube = test::unit_cube_surface();
  VertexMatrix short_normals(7, 3);
  EXPECT_TRUE(throws_with_message<Error>(
      [&] { vertex_normals(cube.vertices, cube.triangles, short_normals); },
      "normals has 7 rows, expected 8 (one per vertex)"));
  TriangleMatrix triangles = cube.triangles;
  triangles(5, 1) = -1;
  VertexMatrix normals = VertexMatrix::Constant(8, 3, 7.0);
  EXPECT_TRUE(
      throws_with_message<MeshError>([&] { vertex_normals(cube.vertices, triangles, normals); },
                                     "triangle 5 uses vertex -1, outside [0, 8)"));
  EXPECT_EQ(normals, VertexMatrix::Constant(8, 3, 7.0));  // untouched
}

}  // namespace
}  // namespace khz::reduced
