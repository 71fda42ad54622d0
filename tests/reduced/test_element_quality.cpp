#include <khz/reduced/errors.hpp>
#include <khz/reduced/mesh/element_quality.hpp>
#include <khz/reduced/meshing/box_mesh.hpp>
#include <khz/test/fixtures.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <sstream>
#include <utility>

namespace khz::reduced {
namespace {

using test::throws_with_message;

VolumeMesh unit_cube_hex() { return box_hex_mesh({0, 0, 0}, {1, 1, 1}, {1, 1, 1}); }

/// The regular tetrahedron with edge length 2√2, positively oriented.
VolumeMesh regular_tet() {
  VolumeMesh mesh;
  mesh.vertices.resize(4, 3);
  mesh.vertices << 1, 1, 1, -1, 1, -1, 1, -1, -1, -1, -1, 1;
  mesh.elements.resize(1, 4);
  mesh.elements << 0, 1, 2, 3;
  return mesh;
}

/// 2×1×1 box in tetrahedra (12 elements of volume 1/6) with element `e` turned inside out.
VolumeMesh tets_with_inverted(Eigen::Index e) {
  VolumeMesh mesh = box_tet_mesh({0, 0, 0}, {2, 1, 1}, {2, 1, 1});
  std::swap(mesh.elements(e, 1), mesh.elements(e, 2));
  return mesh;
}

TEST(ElementQuality, CubeHasQualityOneAndUnitVolume) {
  const QualityReport report = analyze_elements(unit_cube_hex());
  ASSERT_EQ(report.volume.size(), 1u);
  EXPECT_DOUBLE_EQ(report.volume[0], 1.0);  // Gauss points at ±1/√3 round
  EXPECT_EQ(report.quality[0], 1.0);
  EXPECT_EQ(report.first_bad_element, -1);
}

TEST(ElementQuality, DistortedHexHasVolumeOfTrilinearMapAndLowerQuality) {
  // Lifting node 6, the (1,1,1) corner, by 1 bulges the top face by the bilinear hat of that
  // node, whose integral over the unit face is 1/4.
  VolumeMesh mesh = unit_cube_hex();
  mesh.vertices(mesh.elements(0, 6), 2) += 1.0;
  const QualityReport report = analyze_elements(mesh);
  EXPECT_NEAR(report.volume[0], 1.25, 1e-15);
  // At node 6, J's columns are (½,0,½), (0,½,½), (0,0,1): det ¼ over lengths ½·1 gives ½.
  EXPECT_NEAR(report.quality[0], 1.0 / 2.0, 1e-15);
}

TEST(ElementQuality, RegularTetHasDihedralArccosOneThird) {
  const QualityReport report = analyze_elements(regular_tet());
  EXPECT_NEAR(report.quality[0], std::acos(1.0 / 3.0), 1e-15);
  EXPECT_NEAR(report.volume[0], 8.0 / 3.0, 1e-15);
}

TEST(ElementQuality, KuhnTetHasQuarterPiDihedral) {
  const QualityReport report = analyze_elements(box_tet_mesh({0, 0, 0}, {1, 1, 1}, {1, 1, 1}));
  for (const double quality : report.quality) EXPECT_NEAR(quality, std::numbers::pi / 4, 1e-15);
}

TEST(ElementQuality, InvertedTetIsFoundWithItsIndex) {
  const QualityReport report = analyze_elements(tets_with_inverted(7));
  EXPECT_EQ(report.num_inverted, 1);
  EXPECT_EQ(report.num_degenerate, 0);
  EXPECT_EQ(report.first_bad_element, 7);
  EXPECT_NEAR(report.volume[7], -1.0 / 6.0, 1e-16);
  EXPECT_LT(report.quality[7], 0.0);
  EXPECT_EQ(report.min_volume, report.volume[7]);
}

TEST(ElementQuality, InvertedHexIsFound) {
  VolumeMesh mesh = box_hex_mesh({0, 0, 0}, {3, 1, 1}, {3, 1, 1});
  // Swapping the bottom and top faces of element 2 mirrors it.
  for (int a = 0; a < 4; ++a) std::swap(mesh.elements(2, a), mesh.elements(2, a + 4));
  const QualityReport report = analyze_elements(mesh);
  EXPECT_EQ(report.num_inverted, 1);
  EXPECT_EQ(report.first_bad_element, 2);
  EXPECT_DOUBLE_EQ(report.volume[2], -1.0);
  EXPECT_EQ(report.quality[2], -1.0);
}

TEST(ElementQuality, FlatTetIsDegenerate) {
  VolumeMesh mesh = regular_tet();
  mesh.vertices.row(3) = (mesh.vertices.row(0) + mesh.vertices.row(1) + mesh.vertices.row(2)) / 3;
  const QualityReport report = analyze_elements(mesh);
  EXPECT_EQ(report.num_degenerate, 1);
  EXPECT_EQ(report.num_inverted, 0);
  EXPECT_EQ(report.first_bad_element, 0);
  EXPECT_NEAR(report.quality[0], 0.0, 1e-7);
}

TEST(ElementQuality, HexCollapsedAtACornerIsDegenerate) {
  // Moving node 6 onto node 5 collapses the edge between them: positive volume, but a zero
  // Jacobian at both corners.
  VolumeMesh mesh = unit_cube_hex();
  mesh.vertices.row(mesh.elements(0, 6)) = mesh.vertices.row(mesh.elements(0, 5));
  const QualityReport report = analyze_elements(mesh);
  EXPECT_GT(report.volume[0], 0.0);
  EXPECT_EQ(report.quality[0], 0.0);
  EXPECT_EQ(report.num_degenerate, 1);
  EXPECT_EQ(report.first_bad_element, 0);
}

TEST(ElementQuality, DegeneracyToleranceScalesWithTheMeshSize) {
  // The bounding-box diagonal of [0,1]×[0,1]×[0,2] is √6.
  const QualityReport report = analyze_elements(box_hex_mesh({0, 0, 0}, {1, 1, 2}, {1, 1, 2}));
  EXPECT_NEAR(report.tolerance, 1e-12 * 6 * std::sqrt(6.0), 1e-26);
}

TEST(ElementQuality, StatisticsSummarizeAllElements) {
  const QualityReport report = analyze_elements(tets_with_inverted(0));
  EXPECT_NEAR(report.total_volume, 2.0 - 2.0 / 6.0, 1e-15);
  EXPECT_NEAR(report.max_volume, 1.0 / 6.0, 1e-16);
  EXPECT_NEAR(report.max_quality, std::numbers::pi / 4, 1e-15);
  EXPECT_NEAR(report.mean_quality, std::numbers::pi / 4 * 10.0 / 12.0, 1e-15);
}

TEST(ElementQuality, EmptyMeshHasZeroStatistics) {
  const QualityReport report = analyze_elements(VolumeMesh{});
  EXPECT_TRUE(report.volume.empty());
  EXPECT_EQ(report.total_volume, 0.0);
  EXPECT_EQ(report.mean_quality, 0.0);
  EXPECT_EQ(report.first_bad_element, -1);
}

TEST(ElementQuality, InvalidMeshIsRejected) {
  VolumeMesh mesh = regular_tet();
  mesh.elements(0, 3) = 4;
  EXPECT_TRUE(throws_with_message<MeshError>([&] { analyze_elements(mesh); }, "element 0"));
}

TEST(ElementQuality, ReportPrintsCountsAndFirstBadElement) {
  std::ostringstream out;
  out << analyze_elements(tets_with_inverted(7));
  EXPECT_NE(out.str().find("12 tetrahedra"), std::string::npos) << out.str();
  EXPECT_NE(out.str().find("inverted:        1"), std::string::npos) << out.str();
  EXPECT_NE(out.str().find("element 7"), std::string::npos) << out.str();
}

TEST(RequireValidElements, AcceptsValidMeshes) {
  EXPECT_NO_THROW(require_valid_elements(box_tet_mesh({0, 0, 0}, {1, 2, 3}, {2, 3, 4})));
  EXPECT_NO_THROW(require_valid_elements(box_hex_mesh({0, 0, 0}, {1, 2, 3}, {2, 3, 4})));
}

TEST(RequireValidElements, NamesFirstInvertedTetAndItsVolume) {
  VolumeMesh mesh = tets_with_inverted(9);
  std::swap(mesh.elements(11, 0), mesh.elements(11, 3));
  try {
    require_valid_elements(mesh);
    FAIL() << "did not throw";
  } catch (const MeshError& error) {
    EXPECT_EQ(error.element(), 9);
    EXPECT_NE(std::string(error.what()).find("element 9 is inverted (signed volume -0.166667 m³"),
              std::string::npos)
        << error.what();
  }
}

TEST(RequireValidElements, NamesDegenerateTet) {
  VolumeMesh mesh = regular_tet();
  mesh.vertices.row(3) = mesh.vertices.row(0);
  EXPECT_TRUE(throws_with_message<MeshError>([&] { require_valid_elements(mesh); },
                                             "element 0 is degenerate (signed volume "));
}

TEST(RequireValidElements, NamesInvertedHexAndItsCornerJacobian) {
  VolumeMesh mesh = unit_cube_hex();
  for (int a = 0; a < 4; ++a) std::swap(mesh.elements(0, a), mesh.elements(0, a + 4));
  EXPECT_TRUE(throws_with_message<MeshError>(
      [&] { require_valid_elements(mesh); },
      "element 0 is inverted (minimum corner Jacobian determinant -0.125 m³, volume -1 m³"));
}

}  // namespace
}  // namespace khz::reduced
