#include <khz/reduced/errors.hpp>
#include <khz/reduced/io/mesh_file.hpp>
#include <khz/reduced/mesh/mesh_repair.hpp>
#include <khz/reduced/mesh/mesh_report.hpp>
#include <khz/test/fixtures.hpp>
#include <khz/test/generated_meshes.hpp>

#include <gtest/gtest.h>

namespace khz::reduced {
namespace {

/// The unit cube without its z = 1 face (its triangles 2 and 3): one square hole.
TriangleMesh open_box() {
  const TriangleMesh cube = test::unit_cube_surface();
  TriangleMesh box = cube;
  box.triangles.resize(10, 3);
  box.triangles << cube.triangles.topRows(2), cube.triangles.bottomRows(8);
  return box;
}

TEST(FillHoles, ClosesABoxIntoTheUnitCube) {
  TriangleMesh box = open_box();
  ASSERT_EQ(analyze_mesh(box).num_boundary_edges, 4);
  const HoleFilling filling = fill_holes(box);
  EXPECT_EQ(filling.filled, 1);
  EXPECT_EQ(filling.left_open, 0);
  const MeshReport report = analyze_mesh(box);
  EXPECT_EQ(report.num_triangles, 12);
  EXPECT_TRUE(report.closed);
  EXPECT_TRUE(report.consistently_oriented);
  EXPECT_NEAR(report.signed_volume, 1.0, 1e-15);  // outward: the cap faces +z
}

TEST(FillHoles, LeavesAClosedMeshAlone) {
  TriangleMesh cube = test::unit_cube_surface();
  const HoleFilling filling = fill_holes(cube);
  EXPECT_EQ(filling.filled, 0);
  EXPECT_EQ(cube.triangles, test::unit_cube_surface().triangles);
}

TEST(FillHoles, ClosesTheHolesOfTheChineseDragonScan) {
  TriangleMesh dragon = read_triangle_mesh(test::cgal_mesh("ChineseDragon-10kv.off"));
  const MeshReport before = analyze_mesh(dragon);
  ASSERT_GT(before.num_boundary_edges, 0);
  const HoleFilling filling = fill_holes(dragon);
  EXPECT_GT(filling.filled, 0);
  EXPECT_EQ(filling.left_open, 0);
  const MeshReport after = analyze_mesh(dragon);
  EXPECT_TRUE(after.closed);
  EXPECT_TRUE(after.consistently_oriented);
  EXPECT_GT(after.signed_volume, 0.0);
  // A loop of n edges takes n − 2 triangles over its own vertices.
  EXPECT_EQ(after.num_triangles,
            before.num_triangles + before.num_boundary_edges - 2 * filling.filled);
  EXPECT_EQ(after.num_vertices, before.num_vertices);
}

TEST(FillHoles, LeavesOpenWhatWouldBecomeNonManifold) {
  // Many holes, some bridged by surface edges where they nearly meet.
  TriangleMesh elephant = read_triangle_mesh(test::cgal_mesh("elephant-with-holes.off"));
  const Eigen::Index open_before = analyze_mesh(elephant).num_boundary_edges;
  const HoleFilling filling = fill_holes(elephant);
  const MeshReport after = analyze_mesh(elephant);
  EXPECT_TRUE(after.edge_manifold && after.consistently_oriented);
  EXPECT_GT(filling.filled, 0);
  EXPECT_GT(filling.left_open, 0);
  // The holes left open keep their boundary edges; the filled ones lose theirs.
  EXPECT_GT(after.num_boundary_edges, 0);
  EXPECT_LT(after.num_boundary_edges, open_before);
}

TEST(FillHoles, RefusesAnInconsistentlyOrientedMesh) {
  TriangleMesh box = open_box();
  box.triangles.row(0) = box.triangles.row(0).reverse().eval();
  EXPECT_TRUE(test::throws_with_message<MeshError>(
      [&] { fill_holes(box); },
      "fill_holes needs an edge-manifold, consistently oriented surface"));
}

}  // namespace
}  // namespace khz::reduced
