#include <khz/reduced/errors.hpp>
#include <khz/reduced/mesh/triangle_mesh.hpp>
#include <khz/reduced/mesh/volume_mesh.hpp>
#include <khz/test/fixtures.hpp>
#include <khz/test/generated_meshes.hpp>

#include <gtest/gtest.h>

#include <limits>

namespace khz::reduced {
namespace {

using test::throws_with_message;

VolumeMesh single_tetrahedron() {
  VolumeMesh mesh;
  mesh.vertices.resize(4, 3);
  mesh.vertices << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1;
  mesh.elements.resize(1, 4);
  mesh.elements << 0, 1, 2, 3;
  return mesh;
}

TEST(ValidateTriangleMesh, AcceptsGeneratedMeshes) {
  EXPECT_NO_THROW(validate(test::unit_cube_surface()));
  EXPECT_NO_THROW(validate(test::random_soup(10, 1)));
  EXPECT_NO_THROW(validate(TriangleMesh{}));
}

TEST(ValidateTriangleMesh, NamesTriangleWithIndexOutOfRange) {
  TriangleMesh mesh = test::unit_cube_surface();
  mesh.triangles(7, 2) = 8;
  EXPECT_TRUE(throws_with_message<MeshError>([&] { validate(mesh); },
                                             "triangle 7 uses vertex 8, outside [0, 8)"));
  mesh.triangles(7, 2) = -1;
  EXPECT_TRUE(throws_with_message<MeshError>([&] { validate(mesh); }, "triangle 7 uses vertex -1"));
}

TEST(ValidateTriangleMesh, NamesVertexWithNonFiniteCoordinate) {
  TriangleMesh mesh = test::unit_cube_surface();
  mesh.vertices(5, 1) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_TRUE(throws_with_message<MeshError>([&] { validate(mesh); },
                                             "vertex 5 has a non-finite coordinate"));
  mesh.vertices(5, 1) = std::numeric_limits<double>::infinity();
  EXPECT_TRUE(throws_with_message<MeshError>([&] { validate(mesh); }, "vertex 5"));
}

TEST(ValidateTriangleMesh, ChecksColours) {
  TriangleMesh mesh = test::random_soup(2, 3);
  mesh.vertex_colors(4, 3) = 1.5f;
  EXPECT_TRUE(throws_with_message<MeshError>([&] { validate(mesh); },
                                             "vertex 4 has a colour channel outside [0, 1]"));
  mesh.vertex_colors.conservativeResize(5, 4);
  EXPECT_TRUE(
      throws_with_message<MeshError>([&] { validate(mesh); }, "5 vertex colours for 6 vertices"));
}

TEST(ValidateVolumeMesh, AcceptsTetrahedron) { EXPECT_NO_THROW(validate(single_tetrahedron())); }

TEST(ValidateVolumeMesh, RejectsWrongElementWidth) {
  VolumeMesh mesh = single_tetrahedron();
  mesh.element_type = ElementType::hexahedron;
  EXPECT_TRUE(throws_with_message<MeshError>([&] { validate(mesh); },
                                             "elements have 4 nodes, the element type needs 8"));
}

TEST(ValidateVolumeMesh, RejectsRepeatedNode) {
  VolumeMesh mesh = single_tetrahedron();
  mesh.elements(0, 3) = 1;
  EXPECT_TRUE(
      throws_with_message<MeshError>([&] { validate(mesh); }, "element 0 uses vertex 1 twice"));
}

TEST(ValidateVolumeMesh, RejectsBadGroups) {
  VolumeMesh mesh = single_tetrahedron();
  mesh.element_groups = Eigen::VectorXi::Constant(1, -2);
  EXPECT_TRUE(
      throws_with_message<MeshError>([&] { validate(mesh); }, "element 0 has negative group -2"));
  mesh.element_groups = Eigen::VectorXi::Zero(2);
  EXPECT_TRUE(
      throws_with_message<MeshError>([&] { validate(mesh); }, "2 element groups for 1 elements"));
}

TEST(ValidateVolumeMesh, RejectsIndexOutOfRange) {
  VolumeMesh mesh = single_tetrahedron();
  mesh.elements(0, 2) = 4;
  EXPECT_TRUE(throws_with_message<MeshError>([&] { validate(mesh); },
                                             "element 0 uses vertex 4, outside [0, 4)"));
}

}  // namespace
}  // namespace khz::reduced
