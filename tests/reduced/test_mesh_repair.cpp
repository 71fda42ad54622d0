#include <khz/reduced/errors.hpp>
#include <khz/reduced/io/off.hpp>
#include <khz/reduced/mesh/mesh_repair.hpp>
#include <khz/reduced/mesh/mesh_report.hpp>
#include <khz/test/fixtures.hpp>
#include <khz/test/generated_meshes.hpp>

#include <khz/test/mesh_edits.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

namespace khz::reduced {
namespace {

using test::unit_cube_surface;
using test::with_flipped;
using test::with_triangle;
using test::with_vertex;

/// Each triangle of `mesh` with its own three vertices 3t, 3t+1, 3t+2 (colours are dropped).
TriangleMesh as_soup(const TriangleMesh& mesh) {
  TriangleMesh soup;
  soup.vertices.resize(3 * mesh.num_triangles(), 3);
  soup.triangles.resize(mesh.num_triangles(), 3);
  for (Eigen::Index t = 0; t < mesh.num_triangles(); ++t) {
    for (int k = 0; k < 3; ++k) {
      soup.vertices.row(3 * t + k) = mesh.vertices.row(mesh.triangles(t, k));
      soup.triangles(t, k) = static_cast<int>(3 * t + k);
    }
  }
  return soup;
}

TEST(WeldVertices, ExactWeldTurnsCubeSoupBackIntoCube) {
  TriangleMesh mesh = as_soup(unit_cube_surface());
  EXPECT_EQ(weld_vertices(mesh), 36 - 8);
  EXPECT_EQ(mesh.num_vertices(), 8);
  const MeshReport report = analyze_mesh(mesh);
  EXPECT_TRUE(report.closed);
  EXPECT_TRUE(report.consistently_oriented);
  EXPECT_EQ(report.signed_volume, 1.0);
}

TEST(WeldVertices, MergedVertexKeepsColourOfLowestIndex) {
  TriangleMesh mesh = as_soup(unit_cube_surface());
  mesh.vertex_colors = ColorMatrix::Zero(mesh.num_vertices(), 4);
  for (Eigen::Index v = 0; v < mesh.num_vertices(); ++v) mesh.vertex_colors(v, 0) = v / 36.0f;
  // Survivors are the first occurrence of each position, in soup order.
  ColorMatrix expected(8, 4);
  VertexMatrix seen(8, 3);
  Eigen::Index count = 0;
  for (Eigen::Index v = 0; v < mesh.num_vertices(); ++v) {
    if (((seen.topRows(count).rowwise() - mesh.vertices.row(v)).rowwise().squaredNorm().array() ==
         0.0)
            .any()) {
      continue;
    }
    seen.row(count) = mesh.vertices.row(v);
    expected.row(count++) = mesh.vertex_colors.row(v);
  }
  weld_vertices(mesh);
  EXPECT_EQ(mesh.vertices, seen);
  EXPECT_EQ(mesh.vertex_colors, expected);
}

TEST(WeldVertices, ToleranceMergesCloseButNotDistantVertices) {
  // Soup of the square: vertices 3 and 4 are second copies of corners 0 and 2.
  TriangleMesh mesh = as_soup(test::unit_square());
  mesh.vertices(3, 0) += 1e-9;
  mesh.vertices(4, 0) += 1e-3;
  EXPECT_EQ(weld_vertices(mesh, 1e-6), 1);
  EXPECT_EQ(mesh.num_vertices(), 5);
  EXPECT_EQ(mesh.vertices.row(0), Eigen::RowVector3d(0, 0, 0));  // the lower index wins
}

TEST(WeldVertices, ChainsOfCloseVerticesMergeTransitively) {
  TriangleMesh mesh;
  mesh.vertices.resize(3, 3);
  mesh.vertices << 0, 0, 0, 0.9, 0, 0, 1.8, 0, 0;
  mesh.triangles.resize(1, 3);
  mesh.triangles << 0, 1, 2;
  EXPECT_EQ(weld_vertices(mesh, 1.0), 2);
  EXPECT_EQ(mesh.triangles.row(0), Eigen::RowVector3i(0, 0, 0));
}

TEST(WeldVertices, UnreferencedVertexDoesNotBridgeMerges) {
  TriangleMesh mesh;
  mesh.vertices.resize(4, 3);
  mesh.vertices << 0, 0, 0, 1.6, 0, 0, 0, 5, 0, 0.8, 0, 0;  // vertex 3 is unused
  mesh.triangles.resize(1, 3);
  mesh.triangles << 0, 1, 2;
  EXPECT_EQ(weld_vertices(mesh, 1.0), 1);
  EXPECT_EQ(mesh.num_vertices(), 3);
}

TEST(WeldVertices, MatchesAllPairsClusteringOnRandomPoints) {
  TriangleMesh mesh = test::random_soup(200, 7);
  const double tolerance = 0.12;
  // Reference: connected components of the "within tolerance" graph, by flood fill.
  const Eigen::Index n = mesh.num_vertices();
  std::vector<bool> visited(n);
  Eigen::Index clusters = 0;
  for (Eigen::Index seed = 0; seed < n; ++seed) {
    if (visited[seed]) continue;
    ++clusters;
    std::vector<Eigen::Index> stack{seed};
    visited[seed] = true;
    while (!stack.empty()) {
      const Eigen::Index v = stack.back();
      stack.pop_back();
      for (Eigen::Index w = 0; w < n; ++w) {
        if (!visited[w] && (mesh.vertices.row(v) - mesh.vertices.row(w)).norm() <= tolerance) {
          visited[w] = true;
          stack.push_back(w);
        }
      }
    }
  }
  ASSERT_LT(clusters, n - 50);  // the test needs plenty of merges, chains included
  TriangleMesh reversed = mesh;
  reversed.vertices = mesh.vertices.colwise().reverse();
  for (int& v : reversed.triangles.reshaped()) v = static_cast<int>(n - 1 - v);

  EXPECT_EQ(weld_vertices(mesh, tolerance), n - clusters);
  EXPECT_EQ(weld_vertices(reversed, tolerance), n - clusters);
}

TEST(WeldVertices, DropsUnreferencedVertices) {
  TriangleMesh mesh = with_vertex(unit_cube_surface(), 5, 5, 5);
  EXPECT_EQ(weld_vertices(mesh), 1);
  EXPECT_EQ(mesh.vertices, unit_cube_surface().vertices);
  EXPECT_EQ(mesh.triangles, unit_cube_surface().triangles);
}

TEST(WeldVertices, RejectsBadTolerance) {
  for (const double tolerance :
       {-1e-6, std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()}) {
    TriangleMesh mesh = unit_cube_surface();
    EXPECT_TRUE(test::throws_with_message<MeshError>([&] { weld_vertices(mesh, tolerance); },
                                                     "weld tolerance"));
  }
}

TEST(WeldVertices, RejectsInvalidMesh) {
  TriangleMesh mesh = unit_cube_surface();
  mesh.vertices(2, 1) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(weld_vertices(mesh), MeshError);
}

TEST(RemoveDegenerateTriangles, RemovesExactlyDegenerateAndDuplicateOnes) {
  TriangleMesh mesh = with_vertex(unit_cube_surface(), 0.5, 0, 0);  // vertex 8, on edge 0–1
  mesh = with_triangle(mesh, 2, 2, 3);                              // repeated index
  mesh = with_triangle(mesh, 0, 8, 1);                              // zero area
  mesh = with_triangle(mesh, 6, 4, 2);                              // triangle 9 (2, 4, 6) again
  mesh = with_triangle(mesh, 0, 1, 5);  // overlaps a face, but is a proper triangle
  EXPECT_EQ(remove_degenerate_triangles(mesh), 3);
  TriangleMatrix expected(13, 3);
  expected << unit_cube_surface().triangles, 0, 1, 5;
  EXPECT_EQ(mesh.triangles, expected);
  EXPECT_EQ(mesh.num_vertices(), 9);
}

TEST(RemoveDegenerateTriangles, KeepsTheFirstOfDuplicates) {
  TriangleMesh mesh = unit_cube_surface();
  mesh.triangles.row(11) = mesh.triangles.row(0);
  EXPECT_EQ(remove_degenerate_triangles(mesh), 1);
  EXPECT_EQ(mesh.triangles, unit_cube_surface().triangles.topRows(11));
}

TEST(RemoveDegenerateTriangles, LeavesCleanMeshAlone) {
  TriangleMesh mesh = test::uv_sphere(16, 8);
  EXPECT_EQ(remove_degenerate_triangles(mesh), 0);
  EXPECT_EQ(mesh.triangles, test::uv_sphere(16, 8).triangles);
}

TEST(OrientConsistently, FixesFlippedTriangles) {
  TriangleMesh mesh = with_flipped(with_flipped(with_flipped(unit_cube_surface(), 1), 5), 9);
  EXPECT_TRUE(orient_consistently(mesh));
  const MeshReport report = analyze_mesh(mesh);
  EXPECT_TRUE(report.consistently_oriented);
  EXPECT_EQ(report.signed_volume, 1.0);
}

TEST(OrientConsistently, TurnsInsideOutCubeOutward) {
  TriangleMesh mesh = unit_cube_surface();
  mesh.triangles.rowwise().reverseInPlace();
  ASSERT_EQ(analyze_mesh(mesh).signed_volume, -1.0);
  EXPECT_TRUE(orient_consistently(mesh));
  EXPECT_EQ(analyze_mesh(mesh).signed_volume, 1.0);
}

TEST(OrientConsistently, LeavesOrientedMeshUnchanged) {
  TriangleMesh mesh = test::uv_sphere(16, 8);
  EXPECT_TRUE(orient_consistently(mesh));
  EXPECT_EQ(mesh.triangles, test::uv_sphere(16, 8).triangles);
  EXPECT_EQ(mesh.vertices, test::uv_sphere(16, 8).vertices);
}

TEST(OrientConsistently, OrientsOpenSurface) {
  TriangleMesh mesh = with_flipped(test::unit_square(), 1);
  EXPECT_TRUE(orient_consistently(mesh));
  EXPECT_TRUE(analyze_mesh(mesh).consistently_oriented);
}

TEST(OrientConsistently, NestedShellsBoundAVolume) {
  TriangleMesh outer = unit_cube_surface();
  outer.vertices *= 3.0;
  TriangleMesh mesh = test::combined(outer, unit_cube_surface(), Eigen::RowVector3d(1, 1, 1));
  EXPECT_TRUE(orient_consistently(mesh));
  // The inner cube now faces inwards: the volume is the space between the shells.
  EXPECT_EQ(analyze_mesh(mesh).signed_volume, 27.0 - 1.0);
}

TEST(OrientConsistently, TurnsOverlappingInsideOutCubesOutward) {
  // Self-intersecting, so CGAL's volume orientation does not apply; each cube is turned
  // outward on its own.
  TriangleMesh mesh =
      test::combined(unit_cube_surface(), unit_cube_surface(), Eigen::RowVector3d(0.5, 0.5, 0.5));
  mesh.triangles.rowwise().reverseInPlace();
  EXPECT_TRUE(orient_consistently(mesh));
  EXPECT_EQ(analyze_mesh(mesh).signed_volume, 2.0);
}

TEST(OrientConsistently, SplitsBowTieVertexAndCopiesItsColour) {
  TriangleMesh mesh = with_flipped(test::cubes_sharing_a_corner(), 20);
  mesh.vertex_colors = ColorMatrix::Ones(mesh.num_vertices(), 4);
  for (Eigen::Index v = 0; v < mesh.num_vertices(); ++v) mesh.vertex_colors(v, 0) = v / 15.0f;
  EXPECT_TRUE(orient_consistently(mesh));
  ASSERT_EQ(mesh.num_vertices(), 16);
  EXPECT_EQ(mesh.vertices.row(15), mesh.vertices.row(7));
  EXPECT_EQ(mesh.vertex_colors.row(15), mesh.vertex_colors.row(7));
  const MeshReport report = analyze_mesh(mesh);
  EXPECT_TRUE(report.vertex_manifold);
  EXPECT_TRUE(report.closed);
  EXPECT_EQ(report.num_components, 2);
  EXPECT_EQ(report.signed_volume, 2.0);
}

TEST(OrientConsistently, SplitsNonManifoldEdge) {
  TriangleMesh mesh;
  mesh.vertices.resize(5, 3);
  mesh.vertices << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1;
  mesh.triangles.resize(3, 3);
  mesh.triangles << 0, 1, 2, 1, 0, 3, 0, 1, 4;
  EXPECT_TRUE(orient_consistently(mesh));
  EXPECT_GT(mesh.num_vertices(), 5);
  EXPECT_TRUE(analyze_mesh(mesh).edge_manifold);
}

TEST(OrientConsistently, LeavesRepeatedIndexTriangleAlone) {
  TriangleMesh mesh = with_triangle(with_flipped(unit_cube_surface(), 4), 2, 2, 3);
  EXPECT_TRUE(orient_consistently(mesh));
  EXPECT_EQ(mesh.triangles.row(12), Eigen::RowVector3i(2, 2, 3));
  EXPECT_EQ(analyze_mesh(mesh).signed_volume, 1.0);
}

TEST(OrientConsistently, RejectsInvalidMesh) {
  TriangleMesh mesh = with_triangle(unit_cube_surface(), 0, 1, -1);
  EXPECT_THROW(orient_consistently(mesh), MeshError);
}

TEST(RepairMesh, CleansMessyCubeSoup) {
  TriangleMesh mesh = as_soup(with_flipped(with_flipped(unit_cube_surface(), 2), 7));
  // Jitter every corner by up to 1e-9, then add a duplicate and a repeated-index triangle.
  for (Eigen::Index v = 0; v < mesh.num_vertices(); ++v) {
    mesh.vertices.row(v) +=
        1e-9 * Eigen::RowVector3d(double(v % 3) - 1, double(v % 5 % 3) - 1, double(v % 7 % 3) - 1);
  }
  mesh = with_triangle(with_triangle(mesh, 0, 1, 2), 3, 4, 3);
  RepairOptions options;
  options.weld_tolerance = 1e-6;
  const RepairSummary summary = repair_mesh(mesh, options);
  EXPECT_EQ(summary.vertices_welded, 36 - 8);
  EXPECT_EQ(summary.triangles_removed, 2);
  EXPECT_TRUE(summary.oriented);
  const MeshReport report = analyze_mesh(mesh);
  EXPECT_EQ(report.num_vertices, 8);
  EXPECT_EQ(report.num_triangles, 12);
  EXPECT_TRUE(report.closed);
  EXPECT_TRUE(report.consistently_oriented);
  EXPECT_NEAR(report.signed_volume, 1.0, 1e-8);
}

TEST(RepairMesh, NegativeToleranceSkipsWelding) {
  TriangleMesh mesh = as_soup(unit_cube_surface());
  RepairOptions options;
  options.weld_tolerance = -1.0;
  options.orient = false;
  const RepairSummary summary = repair_mesh(mesh, options);
  EXPECT_EQ(summary.vertices_welded, 0);
  EXPECT_FALSE(summary.oriented);
  EXPECT_EQ(mesh.num_vertices(), 36);
}

TEST(RepairMesh, RejectsNanTolerance) {
  TriangleMesh mesh = unit_cube_surface();
  RepairOptions options;
  options.weld_tolerance = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(repair_mesh(mesh, options), MeshError);
}

TriangleMesh read_cgal_mesh(const char* name) {
  const auto path = test::cgal_mesh(name);
  return parse_off(test::read_bytes(path), path.string());
}

TEST(OrientConsistently, OrientsShuffledBlobbyOutward) {
  // Closed but with triangles facing both ways; volume as CGAL's orient_to_bound_a_volume and
  // volume() give it.
  TriangleMesh mesh = read_cgal_mesh("blobby-shuffled.off");
  EXPECT_TRUE(orient_consistently(mesh));
  const MeshReport report = analyze_mesh(mesh);
  EXPECT_TRUE(report.closed);
  EXPECT_TRUE(report.consistently_oriented);
  EXPECT_NEAR(report.signed_volume, 0.050082476255294411, 1e-12);
}

TEST(RepairMesh, CountsTheVerticesOrientingCopiesAfterWelding) {
  // Welding closes pinches between this mesh's holes that orienting then splits again: the
  // summary must say so, since the output keeps duplicate positions although welding ran.
  TriangleMesh oriented = read_cgal_mesh("elephant-with-holes.off");
  TriangleMesh welded_only = oriented;
  RepairOptions options;
  options.weld_tolerance = 1e-6;
  const RepairSummary summary = repair_mesh(oriented, options);
  EXPECT_GT(summary.vertices_welded, 0);
  EXPECT_GT(summary.vertices_split, 0);
  EXPECT_EQ(analyze_mesh(oriented).num_duplicate_vertices, summary.vertices_split);

  options.orient = false;
  const RepairSummary kept = repair_mesh(welded_only, options);
  EXPECT_EQ(kept.vertices_welded, summary.vertices_welded);
  EXPECT_EQ(kept.vertices_split, 0);
  EXPECT_EQ(analyze_mesh(welded_only).num_duplicate_vertices, 0);
}

TEST(OrientConsistently, SplitsPinchedVerticesOfRealMesh) {
  // CGAL's orient_polygon_soup duplicates 3 points at this mesh's 2 pinched vertices.
  TriangleMesh mesh = read_cgal_mesh("polygon_mesh.off");
  EXPECT_TRUE(orient_consistently(mesh));
  EXPECT_EQ(mesh.num_vertices(), 16344 + 3);
  EXPECT_TRUE(analyze_mesh(mesh).vertex_manifold);
}

}  // namespace
}  // namespace khz::reduced
