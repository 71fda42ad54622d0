#include <khz/reduced/errors.hpp>
#include <khz/reduced/io/off.hpp>
#include <khz/reduced/mesh/mesh_report.hpp>
#include <khz/test/fixtures.hpp>
#include <khz/test/generated_meshes.hpp>

#include <khz/test/mesh_edits.hpp>

#include <gtest/gtest.h>

#include <cctype>
#include <cmath>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

namespace khz::reduced {
namespace {

using test::combined;
using test::unit_cube_surface;
using test::with_flipped;
using test::with_triangle;
using test::with_vertex;
using Indices = std::vector<Eigen::Index>;

TEST(MeshReport, CubeIsClosedManifoldAndOriented) {
  const MeshReport report = analyze_mesh(unit_cube_surface());
  EXPECT_TRUE(report.closed);
  EXPECT_TRUE(report.edge_manifold);
  EXPECT_TRUE(report.vertex_manifold);
  EXPECT_TRUE(report.consistently_oriented);
  EXPECT_EQ(report.num_boundary_edges, 0);
  EXPECT_EQ(report.num_non_manifold_edges, 0);
  EXPECT_EQ(report.num_non_manifold_vertices, 0);
}

TEST(MeshReport, CubeCountsElements) {
  const MeshReport report = analyze_mesh(unit_cube_surface());
  EXPECT_EQ(report.num_vertices, 8);
  EXPECT_EQ(report.num_triangles, 12);
  EXPECT_EQ(report.num_edges, 18);
  EXPECT_EQ(report.num_components, 1);
  EXPECT_EQ(report.euler_characteristic, 2);
  EXPECT_EQ(report.num_unreferenced_vertices, 0);
  EXPECT_EQ(report.num_duplicate_vertices, 0);
  EXPECT_TRUE(report.degenerate_triangles.empty());
  EXPECT_TRUE(report.duplicate_triangles.empty());
}

TEST(MeshReport, CubeAreaAndVolumeAreExact) {
  const MeshReport report = analyze_mesh(unit_cube_surface());
  EXPECT_EQ(report.surface_area, 6.0);
  EXPECT_EQ(report.signed_volume, 1.0);
}

TEST(MeshReport, CubeBoundingBoxIsUnitBox) {
  const MeshReport report = analyze_mesh(unit_cube_surface());
  EXPECT_EQ(report.bounding_box.min(), Eigen::Vector3d(0, 0, 0));
  EXPECT_EQ(report.bounding_box.max(), Eigen::Vector3d(1, 1, 1));
}

TEST(MeshReport, SquareIsOpenWithFourBoundaryEdges) {
  const MeshReport report = analyze_mesh(test::unit_square());
  EXPECT_FALSE(report.closed);
  EXPECT_TRUE(report.vertex_manifold);
  EXPECT_TRUE(report.consistently_oriented);
  EXPECT_EQ(report.num_edges, 5);
  EXPECT_EQ(report.num_boundary_edges, 4);
  EXPECT_EQ(report.euler_characteristic, 1);
  EXPECT_EQ(report.surface_area, 1.0);
}

TEST(MeshReport, UvSphereIsClosedWithEulerCharacteristicTwo) {
  const MeshReport report = analyze_mesh(test::uv_sphere(16, 8));
  EXPECT_TRUE(report.closed);
  EXPECT_TRUE(report.consistently_oriented);
  EXPECT_EQ(report.num_vertices, 2 + 7 * 16);
  EXPECT_EQ(report.num_triangles, 2 * 16 * 7);
  EXPECT_EQ(report.euler_characteristic, 2);
}

/// Chord between two points of the unit sphere given by polar and azimuthal angles.
double chord(double theta_a, double phi_a, double theta_b, double phi_b) {
  const double cosine = std::sin(theta_a) * std::sin(theta_b) * std::cos(phi_a - phi_b) +
                        std::cos(theta_a) * std::cos(theta_b);
  return std::sqrt(std::max(0.0, 2.0 - 2.0 * cosine));
}

/// Heron's formula in its numerically stable form (sides sorted a ≥ b ≥ c).
double triangle_area(double a, double b, double c) {
  if (a < b) std::swap(a, b);
  if (a < c) std::swap(a, c);
  if (b < c) std::swap(b, c);
  const double product = (a + (b + c)) * (c - (a - b)) * (c + (a - b)) * (a + (b - c));
  return 0.25 * std::sqrt(std::max(0.0, product));
}

TEST(MeshReport, UvSphereAreaAndVolumeMatchInscribedPolyhedron) {
  // Each band between rings i and i+1 holds, per slice, the triangles (i,j)(i+1,j)(i+1,j+1) and
  // (i,j)(i+1,j+1)(i,j+1); at a pole one of them collapses to nothing. Their volumes seen from
  // the centre are sin θ_{i+1}·sin Δφ·sin Δθ/6 and sin θ_i·sin Δφ·sin Δθ/6.
  const int slices = 16;
  const int stacks = 8;
  const double d_theta = std::numbers::pi / stacks;
  const double d_phi = 2.0 * std::numbers::pi / slices;
  double area = 0.0;
  double volume = 0.0;
  for (int i = 0; i < stacks; ++i) {
    const double upper = i * d_theta;
    const double lower = (i + 1) * d_theta;
    const double meridian = chord(upper, 0, lower, 0);
    const double diagonal = chord(upper, 0, lower, d_phi);
    area += slices * (triangle_area(meridian, chord(lower, 0, lower, d_phi), diagonal) +
                      triangle_area(meridian, chord(upper, 0, upper, d_phi), diagonal));
    volume +=
        slices * (std::sin(upper) + std::sin(lower)) * std::sin(d_phi) * std::sin(d_theta) / 6.0;
  }
  const MeshReport report = analyze_mesh(test::uv_sphere(slices, stacks));
  EXPECT_NEAR(report.surface_area, area, 1e-13);
  EXPECT_NEAR(report.signed_volume, volume, 1e-13);
  EXPECT_LT(report.surface_area, 4.0 * std::numbers::pi);
  EXPECT_LT(report.signed_volume, 4.0 * std::numbers::pi / 3.0);
}

TEST(MeshReport, FlippedTriangleBreaksOrientationOnly) {
  const MeshReport report = analyze_mesh(with_flipped(unit_cube_surface(), 3));
  EXPECT_FALSE(report.consistently_oriented);
  EXPECT_TRUE(report.closed);
  EXPECT_TRUE(report.vertex_manifold);
}

TEST(MeshReport, MissingTriangleLeavesThreeBoundaryEdges) {
  TriangleMesh mesh = unit_cube_surface();
  mesh.triangles.conservativeResize(11, Eigen::NoChange);
  const MeshReport report = analyze_mesh(mesh);
  EXPECT_FALSE(report.closed);
  EXPECT_EQ(report.num_boundary_edges, 3);
  EXPECT_TRUE(report.consistently_oriented);
  EXPECT_EQ(report.euler_characteristic, 1);
}

TEST(MeshReport, DisjointCubesAreTwoComponents) {
  const MeshReport report =
      analyze_mesh(combined(unit_cube_surface(), unit_cube_surface(), Eigen::RowVector3d(2, 0, 0)));
  EXPECT_EQ(report.num_components, 2);
  EXPECT_TRUE(report.closed);
  EXPECT_EQ(report.euler_characteristic, 4);
  EXPECT_EQ(report.signed_volume, 2.0);
}

TEST(MeshReport, CubesSharingACornerHaveOneNonManifoldVertex) {
  const MeshReport report = analyze_mesh(test::cubes_sharing_a_corner());
  EXPECT_EQ(report.num_non_manifold_vertices, 1);
  EXPECT_TRUE(report.edge_manifold);
  EXPECT_FALSE(report.vertex_manifold);
  EXPECT_FALSE(report.closed);
  EXPECT_TRUE(report.consistently_oriented);
  EXPECT_EQ(report.num_components, 2);
}

TEST(MeshReport, ThreeTrianglesOnOneEdgeAreNonManifold) {
  TriangleMesh mesh;
  mesh.vertices.resize(5, 3);
  mesh.vertices << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1;
  mesh.triangles.resize(3, 3);
  mesh.triangles << 0, 1, 2, 1, 0, 3, 0, 1, 4;
  const MeshReport report = analyze_mesh(mesh);
  EXPECT_EQ(report.num_non_manifold_edges, 1);
  EXPECT_EQ(report.num_boundary_edges, 6);
  EXPECT_FALSE(report.edge_manifold);
  EXPECT_FALSE(report.vertex_manifold);
  EXPECT_FALSE(report.consistently_oriented);
  EXPECT_EQ(report.num_non_manifold_vertices, 0);  // its vertices count as the edge
  EXPECT_EQ(report.num_components, 1);
}

TEST(MeshReport, DuplicatedTriangleIsListedAndMakesItsEdgesNonManifold) {
  const MeshReport report = analyze_mesh(with_triangle(unit_cube_surface(), 2, 3, 1));
  EXPECT_EQ(report.duplicate_triangles, Indices{12});
  EXPECT_EQ(report.num_non_manifold_edges, 3);
  EXPECT_FALSE(report.closed);
  EXPECT_TRUE(report.degenerate_triangles.empty());
}

TEST(MeshReport, RepeatedIndexAndZeroAreaTrianglesAreDegenerate) {
  TriangleMesh mesh = with_vertex(unit_cube_surface(), 0.5, 0, 0);  // on edge 0–1
  mesh = with_triangle(with_triangle(mesh, 2, 2, 3), 1, 8, 0);
  EXPECT_EQ(analyze_mesh(mesh).degenerate_triangles, (Indices{12, 13}));
}

TEST(MeshReport, ZeroAreaIsRelativeToTheBoundingBox) {
  // Unit square plus a sliver below edge 0–1; the threshold is 1e-12·diagonal² = 2e-12.
  const auto sliver_report = [](double depth) {
    return analyze_mesh(with_triangle(with_vertex(test::unit_square(), 0.5, -depth, 0), 0, 4, 1));
  };
  EXPECT_EQ(sliver_report(1e-13).degenerate_triangles, Indices{2});
  EXPECT_TRUE(sliver_report(1e-9).degenerate_triangles.empty());
}

TEST(MeshReport, RepeatedIndexTriangleTakesNoPartInTopology) {
  const MeshReport report = analyze_mesh(with_triangle(unit_cube_surface(), 2, 2, 3));
  EXPECT_TRUE(report.closed);
  EXPECT_EQ(report.num_edges, 18);
  EXPECT_EQ(report.num_components, 1);
  EXPECT_EQ(report.euler_characteristic, 2);
}

TEST(MeshReport, ZeroAreaTriangleTakesPartInTopology) {
  const MeshReport report =
      analyze_mesh(with_triangle(with_vertex(test::unit_square(), 0.5, 0, 0), 0, 4, 1));
  EXPECT_EQ(report.degenerate_triangles, Indices{2});
  EXPECT_EQ(report.num_edges, 7);
  EXPECT_EQ(report.num_boundary_edges, 5);
  EXPECT_TRUE(report.consistently_oriented);
  EXPECT_EQ(report.num_components, 1);
}

TEST(MeshReport, ExactDuplicateVertexIsCounted) {
  TriangleMesh mesh = with_vertex(unit_cube_surface(), 1, 1, 0);  // same as vertex 3
  mesh = with_vertex(mesh, 1, 1, std::nextafter(0.0, 1.0));       // not the same
  const MeshReport report = analyze_mesh(mesh);
  EXPECT_EQ(report.num_duplicate_vertices, 1);
  EXPECT_EQ(report.num_unreferenced_vertices, 2);
}

TEST(MeshReport, UnreferencedVertexIsLeftOutOfTheBoundingBox) {
  const MeshReport report = analyze_mesh(with_vertex(unit_cube_surface(), 5, 5, 5));
  EXPECT_EQ(report.num_unreferenced_vertices, 1);
  EXPECT_EQ(report.bounding_box.max(), Eigen::Vector3d(1, 1, 1));
  EXPECT_EQ(report.euler_characteristic, 2);
  EXPECT_TRUE(report.closed);
}

TEST(MeshReport, EmptyMeshHasNothing) {
  const MeshReport report = analyze_mesh(TriangleMesh{});
  EXPECT_TRUE(report.bounding_box.isEmpty());
  EXPECT_EQ(report.num_edges, 0);
  EXPECT_EQ(report.num_components, 0);
  EXPECT_EQ(report.euler_characteristic, 0);
  EXPECT_FALSE(report.closed);
  EXPECT_EQ(report.surface_area, 0.0);
  EXPECT_EQ(report.signed_volume, 0.0);
}

TEST(MeshReport, InvalidMeshThrows) {
  TriangleMesh mesh = with_triangle(unit_cube_surface(), 0, 1, 8);
  EXPECT_TRUE(test::throws_with_message<MeshError>([&] { analyze_mesh(mesh); },
                                                   "triangle 12 uses vertex 8"));
}

TEST(MeshReport, SummaryShowsCountsAndVerdicts) {
  std::ostringstream out;
  out << analyze_mesh(unit_cube_surface());
  const std::string text = out.str();
  for (const char* expected :
       {"vertices:      8 (0 unreferenced", "triangles:     12", "edges:         18 (0 boundary",
        "min (0, 0, 0), max (1, 1, 1), size (1, 1, 1)", "closed:        yes", "oriented:      yes",
        "surface area:  6\n", "volume:        1\n"}) {
    EXPECT_NE(text.find(expected), std::string::npos) << "missing \"" << expected << "\" in\n"
                                                      << text;
  }
}

TEST(MeshReport, SummaryExplainsWhatIsWrong) {
  TriangleMesh mesh = with_flipped(unit_cube_surface(), 0);
  mesh.triangles.conservativeResize(11, Eigen::NoChange);
  std::ostringstream out;
  out << analyze_mesh(mesh);
  const std::string text = out.str();
  for (const char* expected :
       {"closed:        no (3 boundary edges)",
        "oriented:      no (neighbouring triangles disagree)", "volume:        n/a"}) {
    EXPECT_NE(text.find(expected), std::string::npos) << "missing \"" << expected << "\" in\n"
                                                      << text;
  }
}

// CGAL's demo meshes, with facts cross-checked against CGAL (read_polygon_soup,
// is_polygon_soup_a_polygon_mesh, polygon_soup_to_polygon_mesh, is_closed,
// connected_components, is_outward_oriented).
struct RealMesh {
  const char* file;
  Eigen::Index vertices;
  Eigen::Index triangles;
  bool closed;
  bool oriented;
  Eigen::Index components;
  Eigen::Index boundary_edges;
  Eigen::Index non_manifold_vertices;
};

void PrintTo(const RealMesh& mesh, std::ostream* out) { *out << mesh.file; }

class RealMeshReport : public ::testing::TestWithParam<RealMesh> {};

TEST_P(RealMeshReport, AgreesWithCgal) {
  const RealMesh& expected = GetParam();
  const auto path = test::cgal_mesh(expected.file);
  const MeshReport report = analyze_mesh(parse_off(test::read_bytes(path), path.string()));
  EXPECT_EQ(report.num_vertices, expected.vertices);
  EXPECT_EQ(report.num_triangles, expected.triangles);
  EXPECT_EQ(report.closed, expected.closed);
  EXPECT_EQ(report.consistently_oriented, expected.oriented);
  EXPECT_EQ(report.num_components, expected.components);
  EXPECT_EQ(report.num_boundary_edges, expected.boundary_edges);
  EXPECT_EQ(report.num_non_manifold_vertices, expected.non_manifold_vertices);
  EXPECT_EQ(report.num_non_manifold_edges, 0);
  if (expected.closed && expected.oriented) {
    EXPECT_GT(report.signed_volume, 0.0);
  }
}

INSTANTIATE_TEST_SUITE_P(
    CgalDemoMeshes, RealMeshReport,
    ::testing::Values(
        // file, V, F, closed, oriented, components, boundary edges, non-manifold vertices
        RealMesh{"dino.off", 3916, 7828, true, true, 1, 0, 0},
        RealMesh{"ChineseDragon-10kv.off", 10000, 19994, false, true, 1, 6, 0},
        RealMesh{"cow.off", 2904, 5804, true, true, 1, 0, 0},
        RealMesh{"sphere966.off", 926, 1848, true, true, 1, 0, 0},
        RealMesh{"knot2.off", 5760, 11520, true, true, 2, 0, 0},
        RealMesh{"cube-ouvert.off", 9, 10, false, true, 1, 4, 0},
        RealMesh{"elephant-with-holes.off", 2798, 4463, false, true, 1, 1353, 0},
        RealMesh{"mushroom.off", 2337, 4608, false, true, 1, 64, 0},
        // Closed, but CGAL must re-orient it before it is a polygon mesh.
        RealMesh{"blobby-shuffled.off", 2027, 4050, true, false, 1, 0, 0},
        // orient_polygon_soup has to duplicate points at its two pinched vertices.
        RealMesh{"polygon_mesh.off", 16344, 32245, false, true, 1, 489, 2}),
    [](const ::testing::TestParamInfo<RealMesh>& param_info) {
      std::string name = param_info.param.file;
      name = name.substr(0, name.find('.'));
      for (char& c : name) {
        if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
      }
      return name;
    });

}  // namespace
}  // namespace khz::reduced
