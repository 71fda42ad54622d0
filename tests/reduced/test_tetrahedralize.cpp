#include <khz/reduced/errors.hpp>
#include <khz/reduced/io/mesh_file.hpp>
#include <khz/reduced/mesh/element_quality.hpp>
#include <khz/reduced/mesh/mesh_report.hpp>
#include <khz/reduced/meshing/tetrahedralize.hpp>
#include <khz/test/fixtures.hpp>
#include <khz/test/generated_meshes.hpp>
#include <khz/test/mesh_edits.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

namespace khz::reduced {
namespace {

using test::throws_with_message;

/// Coarse criteria so that a Debug test stays near a second (dino.off: about 650 tetrahedra;
/// Mesh_3 unoptimized takes about 1 ms per tetrahedron).
TetrahedralizeOptions coarse_options(const TriangleMesh& surface) {
  const double diagonal = analyze_mesh(surface).bounding_box.diagonal().norm();
  TetrahedralizeOptions options;
  options.facet_size = diagonal / 10;
  options.facet_distance = diagonal / 100;
  return options;
}

const TriangleMesh& dino() {
  static const TriangleMesh mesh = read_triangle_mesh(test::cgal_mesh("dino.off"));
  return mesh;
}

/// The coarse dino mesh, computed once per test program run.
const VolumeMesh& coarse_dino() {
  static const VolumeMesh mesh = tetrahedralize(dino(), coarse_options(dino()));
  return mesh;
}

TEST(Tetrahedralize, DinoGivesValidTetrahedra) {
  const VolumeMesh& mesh = coarse_dino();
  EXPECT_EQ(mesh.element_type, ElementType::tetrahedron);
  EXPECT_GT(mesh.num_elements(), 300);
  EXPECT_EQ(mesh.element_groups.size(), 0);
  EXPECT_NO_THROW(validate(mesh));
  EXPECT_NO_THROW(require_valid_elements(mesh));
}

TEST(Tetrahedralize, AllElementsHavePositiveVolume) {
  const QualityReport report = analyze_elements(coarse_dino());
  EXPECT_GT(report.min_volume, 0.0);
  EXPECT_EQ(report.num_inverted, 0);
  EXPECT_EQ(report.num_degenerate, 0);
}

TEST(Tetrahedralize, VerticesAreNumberedCompactly) {
  const VolumeMesh& mesh = coarse_dino();
  std::vector<bool> used(mesh.num_vertices());
  for (const int v : mesh.elements.reshaped()) used[v] = true;
  EXPECT_EQ(std::count(used.begin(), used.end(), false), 0);
}

TEST(Tetrahedralize, VolumeIsSlightlyBelowTheEnclosedVolume) {
  // The boundary is inscribed in the curved surface (its vertices lie on it), so the mesh is
  // smaller by roughly the facet distance times the area. Measured: −12 % at these coarse
  // criteria (−0.8 % at the defaults, see bench_meshing).
  const double enclosed = analyze_mesh(dino()).signed_volume;
  const double meshed = analyze_elements(coarse_dino()).total_volume;
  EXPECT_GT(meshed / enclosed, 0.86);
  EXPECT_LT(meshed / enclosed, 1.0);
}

TEST(Tetrahedralize, MeshStaysInsideTheSurfaceBoundingBox) {
  const Eigen::AlignedBox3d box = analyze_mesh(dino()).bounding_box;
  const double slack = 1e-9 * box.diagonal().norm();
  const VolumeMesh& mesh = coarse_dino();
  EXPECT_TRUE(
      (mesh.vertices.colwise().minCoeff().transpose().array() >= box.min().array() - slack).all());
  EXPECT_TRUE(
      (mesh.vertices.colwise().maxCoeff().transpose().array() <= box.max().array() + slack).all());
}

TEST(Tetrahedralize, IsDeterministic) {
  const VolumeMesh again = tetrahedralize(dino(), coarse_options(dino()));
  EXPECT_EQ(again.vertices, coarse_dino().vertices);
  EXPECT_EQ(again.elements, coarse_dino().elements);
}

TEST(Tetrahedralize, SphereVolumeConvergesWithFacetDistance) {
  // Halving the facet distance must shrink the volume deficit of the inscribed boundary.
  const TriangleMesh sphere = test::uv_sphere(64, 32);
  const double enclosed = analyze_mesh(sphere).signed_volume;
  TetrahedralizeOptions options = coarse_options(sphere);
  const double coarse = analyze_elements(tetrahedralize(sphere, options)).total_volume;
  options.facet_distance /= 4;
  const double fine = analyze_elements(tetrahedralize(sphere, options)).total_volume;
  EXPECT_LT(coarse, fine);
  EXPECT_LT(fine, enclosed);
  EXPECT_GT(fine / enclosed, 0.97);
}

TEST(Tetrahedralize, RejectsOpenSurface) {
  EXPECT_TRUE(throws_with_message<MeshError>([] { tetrahedralize(test::unit_square()); },
                                             "it is not closed (4 boundary edges)"));
  EXPECT_TRUE(throws_with_message<MeshError>([] { tetrahedralize(test::unit_square()); },
                                             "repair it with repair_mesh(), or voxelize() it"));
}

TEST(Tetrahedralize, RejectsInconsistentOrientation) {
  EXPECT_TRUE(throws_with_message<MeshError>(
      [] { tetrahedralize(test::with_flipped(test::unit_cube_surface(), 3)); },
      "it is not consistently oriented"));
}

TEST(Tetrahedralize, RejectsNonManifoldSurface) {
  EXPECT_TRUE(throws_with_message<MeshError>([] { tetrahedralize(test::cubes_sharing_a_corner()); },
                                             "non-manifold vertices"));
}

TEST(Tetrahedralize, RejectsEmptySurface) {
  EXPECT_TRUE(
      throws_with_message<MeshError>([] { tetrahedralize(TriangleMesh{}); }, "no triangles"));
}

TEST(Tetrahedralize, RejectsOutOfRangeOptions) {
  TetrahedralizeOptions options;
  options.facet_angle = 35;
  EXPECT_TRUE(throws_with_message<Error>(
      [&] { tetrahedralize(test::unit_cube_surface(), options); }, "facet_angle must be in"));
  options = {};
  options.cell_radius_edge_ratio = 1.5;
  EXPECT_TRUE(
      throws_with_message<Error>([&] { tetrahedralize(test::unit_cube_surface(), options); },
                                 "cell_radius_edge_ratio must be finite and >= 2"));
  options = {};
  options.facet_size = -1;
  EXPECT_TRUE(
      throws_with_message<Error>([&] { tetrahedralize(test::unit_cube_surface(), options); },
                                 "facet_size must be finite and >= 0"));
}

}  // namespace
}  // namespace khz::reduced
