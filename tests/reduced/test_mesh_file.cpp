#include <khz/reduced/errors.hpp>
#include <khz/reduced/io/gmsh.hpp>
#include <khz/reduced/io/mesh_file.hpp>
#include <khz/reduced/io/tetgen.hpp>
#include <khz/reduced/io/vtk.hpp>
#include <khz/test/fixtures.hpp>
#include <khz/test/generated_meshes.hpp>

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

namespace khz::reduced {
namespace {

/// The unit cube split into four corner tetrahedra (group 0) around a central one (group 1).
VolumeMesh five_tet_cube() {
  VolumeMesh mesh;
  mesh.vertices.resize(8, 3);
  // Vertex v has x = bit 0, y = bit 1, z = bit 2.
  for (int v = 0; v < 8; ++v) mesh.vertices.row(v) << (v & 1), ((v >> 1) & 1), ((v >> 2) & 1);
  mesh.vertices(7, 0) = 1.0 / 3;  // a coordinate that needs all 17 digits
  mesh.elements.resize(5, 4);
  mesh.elements << 0, 1, 2, 4, 3, 2, 1, 7, 5, 1, 4, 7, 6, 4, 2, 7, 1, 2, 4, 7;
  mesh.element_groups.resize(5);
  mesh.element_groups << 0, 0, 0, 0, 1;
  return mesh;
}

void expect_same(const VolumeMesh& actual, const VolumeMesh& expected) {
  EXPECT_EQ(actual.element_type, expected.element_type);
  ASSERT_EQ(actual.vertices.rows(), expected.vertices.rows());
  ASSERT_EQ(actual.elements.rows(), expected.elements.rows());
  ASSERT_EQ(actual.elements.cols(), expected.elements.cols());
  ASSERT_EQ(actual.element_groups.size(), expected.element_groups.size());
  EXPECT_EQ(actual.vertices, expected.vertices);
  EXPECT_EQ(actual.elements, expected.elements);
  EXPECT_EQ(actual.element_groups, expected.element_groups);
}

void expect_same(const TriangleMesh& actual, const TriangleMesh& expected) {
  ASSERT_EQ(actual.vertices.rows(), expected.vertices.rows());
  ASSERT_EQ(actual.triangles.rows(), expected.triangles.rows());
  EXPECT_EQ(actual.vertices, expected.vertices);
  EXPECT_EQ(actual.triangles, expected.triangles);
}

TEST(MeshFile, VolumeRoundTripThroughMsh) {
  const auto file = test::scratch_file("cube.msh");
  write_volume_mesh(file, five_tet_cube());
  EXPECT_EQ(test::read_bytes(file), format_gmsh(five_tet_cube()));
  expect_same(read_volume_mesh(file), five_tet_cube());
}

TEST(MeshFile, VolumeRoundTripThroughTetgenFromEitherPath) {
  const auto node = test::scratch_file("cube.node");
  const auto ele = test::scratch_file("cube.ele");
  write_volume_mesh(node, five_tet_cube());
  const TetgenFiles files = format_tetgen(five_tet_cube());
  EXPECT_EQ(test::read_bytes(node), files.node);
  EXPECT_EQ(test::read_bytes(ele), files.ele);
  expect_same(read_volume_mesh(node), five_tet_cube());
  expect_same(read_volume_mesh(ele), five_tet_cube());
}

TEST(MeshFile, ExtensionsAreCaseInsensitive) {
  const auto file = test::scratch_file("CUBE.MSH");
  write_volume_mesh(file, five_tet_cube());
  expect_same(read_volume_mesh(file), five_tet_cube());
}

TEST(MeshFile, VolumeVtkAndVtuFilesHoldTheFormattedText) {
  VtkFields fields;
  fields.point_data.push_back({"height", five_tet_cube().vertices.col(2)});
  const auto vtk = test::scratch_file("cube.vtk");
  const auto vtu = test::scratch_file("cube.vtu");
  write_volume_mesh(vtk, five_tet_cube(), fields);
  write_volume_mesh(vtu, five_tet_cube(), fields);
  EXPECT_EQ(test::read_bytes(vtk), format_vtk_legacy(five_tet_cube(), fields));
  EXPECT_EQ(test::read_bytes(vtu), format_vtu(five_tet_cube(), fields));
}

TEST(MeshFile, ReadVolumeMeshRejectsAnElementRepeatingANode) {
  std::string text = test::read_bytes(test::test_file("volume/sparse_tags.msh"));
  text.replace(text.find("10 4 0 100 7"), 12, "10 4 0 100 100");
  const auto file = test::scratch_file("repeated.msh");
  std::ofstream(file) << text;
  EXPECT_TRUE(test::throws_with_message(
      [&] { read_volume_mesh(file); },
      "repeated.msh:15: element 10 lists one node twice (as corners 1 and 2)"));
}

TEST(MeshFile, WriteVolumeMeshValidatesBeforeWriting) {
  VolumeMesh mesh = five_tet_cube();
  mesh.elements(4, 3) = 8;
  const auto file = test::scratch_file("invalid.msh");
  EXPECT_TRUE(test::throws_with_message<MeshError>([&] { write_volume_mesh(file, mesh); },
                                                   "element 4 uses vertex 8"));
  EXPECT_FALSE(std::filesystem::exists(file));
}

TEST(MeshFile, UnknownVolumeExtensionsListTheSupportedOnes) {
  EXPECT_TRUE(test::throws_with_message<Error>([] { read_volume_mesh("mesh.vol"); },
                                               "mesh.vol: unknown mesh file extension '.vol'; "
                                               "supported: .msh .node .ele"));
  EXPECT_TRUE(test::throws_with_message<Error>(
      [] { write_volume_mesh(test::scratch_file("mesh.ele"), five_tet_cube()); },
      "unknown mesh file extension '.ele'; supported: .msh .node .vtk .vtu"));
}

TEST(MeshFile, MissingVolumeFilesAreIoErrorsNamingThePath) {
  const auto msh = test::scratch_file("missing.msh");
  EXPECT_TRUE(test::throws_with_message<IoError>([&] { read_volume_mesh(msh); }, msh.string()));
  // TetGen needs both files: a .node without its .ele names the .ele.
  const auto node = test::scratch_file("lonely.node");
  const auto ele = test::scratch_file("lonely.ele");
  write_volume_mesh(node, five_tet_cube());
  std::filesystem::remove(ele);
  EXPECT_TRUE(test::throws_with_message<IoError>([&] { read_volume_mesh(node); }, ele.string()));
}

TEST(MeshFile, ParseErrorsNameTheFullPath) {
  const auto ele = test::test_file("malformed/tetgen/bad_index.ele");
  const auto node = test::scratch_file("bad_index.node");
  std::filesystem::copy_file(test::test_file("malformed/tetgen/ok.node"), node);
  const auto copied_ele = test::scratch_file("bad_index.ele");
  std::filesystem::copy_file(ele, copied_ele);
  EXPECT_TRUE(test::throws_with_message([&] { read_volume_mesh(node); },
                                        copied_ele.string() +
                                            ":4: tetrahedron 2 uses node 99, but " + node.string() +
                                            " defines nodes 1..4"));
}

TEST(MeshFile, TriangleVtkAndVtuFilesHoldTheFormattedText) {
  const auto vtk = test::scratch_file("square.vtk");
  const auto vtu = test::scratch_file("square.vtu");
  write_triangle_mesh(vtk, test::unit_square());
  write_triangle_mesh(vtu, test::unit_square());
  EXPECT_EQ(test::read_bytes(vtk), format_vtk_legacy(test::unit_square()));
  EXPECT_EQ(test::read_bytes(vtu), format_vtu(test::unit_square()));
}

TEST(MeshFile, UnknownTriangleExtensionsListTheSupportedOnes) {
  EXPECT_TRUE(test::throws_with_message<Error>([] { read_triangle_mesh("mesh.vtk"); },
                                               "unknown mesh file extension '.vtk'; "
                                               "supported: .obj .off .stl .ply"));
  EXPECT_TRUE(test::throws_with_message<Error>(
      [] { write_triangle_mesh(test::scratch_file("mesh"), test::unit_square()); },
      "unknown mesh file extension ''; supported: .obj .off .stl .ply .vtk .vtu"));
}

TEST(MeshFile, MissingTriangleFileIsAnIoErrorNamingThePath) {
  const auto file = test::scratch_file("missing.obj");
  EXPECT_TRUE(test::throws_with_message<IoError>([&] { read_triangle_mesh(file); }, file.string()));
}

// These round trips need the OBJ, OFF, STL and PLY parsers and writers.
TEST(MeshFile, TriangleRoundTripThroughEveryReadableFormat) {
  // unit_square() lists its vertices in the order its triangles first use them, the order an
  // STL reader rebuilds them in.
  for (const char* name : {"square.obj", "square.off", "square.stl", "square.ply"}) {
    for (const bool binary : {true, false}) {
      const auto file = test::scratch_file(name);
      write_triangle_mesh(file, test::unit_square(), {.binary = binary});
      SCOPED_TRACE(std::string(name) + (binary ? " binary" : " ascii"));
      expect_same(read_triangle_mesh(file), test::unit_square());
    }
  }
}

}  // namespace
}  // namespace khz::reduced
