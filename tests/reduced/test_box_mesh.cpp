#include <khz/reduced/errors.hpp>
#include <khz/reduced/fem/element_shape.hpp>
#include <khz/reduced/mesh/element_quality.hpp>
#include <khz/reduced/meshing/box_mesh.hpp>
#include <khz/test/fixtures.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <map>

namespace khz::reduced {
namespace {

using test::throws_with_message;

// Cells of 1×2×3: every Kuhn tetrahedron then has volume exactly 1 and every sum is exact.
const Eigen::Vector3d box_min(-1.0, 0.0, 2.0);
const Eigen::Vector3d box_max(1.0, 6.0, 8.0);
const Eigen::Vector3i box_cells(2, 3, 2);

TEST(BoxMesh, HexCounts) {
  const VolumeMesh mesh = box_hex_mesh(box_min, box_max, box_cells);
  EXPECT_EQ(mesh.element_type, ElementType::hexahedron);
  EXPECT_EQ(mesh.num_vertices(), 3 * 4 * 3);
  EXPECT_EQ(mesh.num_elements(), 2 * 3 * 2);
  EXPECT_EQ(mesh.elements.cols(), 8);
  EXPECT_EQ(mesh.element_groups.size(), 0);
}

TEST(BoxMesh, TetCounts) {
  const VolumeMesh mesh = box_tet_mesh(box_min, box_max, box_cells);
  EXPECT_EQ(mesh.element_type, ElementType::tetrahedron);
  EXPECT_EQ(mesh.num_vertices(), 3 * 4 * 3);
  EXPECT_EQ(mesh.num_elements(), 6 * 2 * 3 * 2);
  EXPECT_EQ(mesh.elements.cols(), 4);
  EXPECT_EQ(mesh.element_groups.size(), 0);
}

TEST(BoxMesh, VerticesAreNumberedXFastestThenYThenZ) {
  for (const VolumeMesh& mesh :
       {box_hex_mesh(box_min, box_max, box_cells), box_tet_mesh(box_min, box_max, box_cells)}) {
    const Eigen::Vector3d step(1.0, 2.0, 3.0);
    for (int k = 0; k <= box_cells.z(); ++k) {
      for (int j = 0; j <= box_cells.y(); ++j) {
        for (int i = 0; i <= box_cells.x(); ++i) {
          const int v = i + 3 * (j + 4 * k);
          const Eigen::Vector3d expected = box_min + Eigen::Vector3d(i, j, k).cwiseProduct(step);
          EXPECT_EQ(mesh.vertices.row(v), expected.transpose()) << "vertex " << v;
        }
      }
    }
  }
}

TEST(BoxMesh, LastLatticeLayerIsExactlyOnMaxCorner) {
  // 0.1 is not representable, so 0 + 3·(0.3/3) need not equal 0.3; the generator must not drift.
  const VolumeMesh mesh = box_hex_mesh({0, 0, 0}, {0.3, 0.7, 0.9}, {3, 7, 9});
  EXPECT_EQ(mesh.vertices.colwise().maxCoeff(), Eigen::RowVector3d(0.3, 0.7, 0.9));
}

TEST(BoxMesh, HexElementsFollowCellNumberingAndVtkNodeOrder) {
  const VolumeMesh mesh = box_hex_mesh(box_min, box_max, box_cells);
  // Cell (1, 2, 1) is element 1 + 2·(2 + 3·1) = 11, with node 0 at lattice point (1, 2, 1).
  const auto vertex = [](int i, int j, int k) { return i + 3 * (j + 4 * k); };
  const std::array<int, 8> expected = {vertex(1, 2, 1), vertex(2, 2, 1), vertex(2, 3, 1),
                                       vertex(1, 3, 1), vertex(1, 2, 2), vertex(2, 2, 2),
                                       vertex(2, 3, 2), vertex(1, 3, 2)};
  for (int a = 0; a < 8; ++a) EXPECT_EQ(mesh.elements(11, a), expected[a]) << "node " << a;
}

TEST(BoxMesh, HexVolumeIsExactAndElementsAreCuboids) {
  const QualityReport report = analyze_elements(box_hex_mesh(box_min, box_max, box_cells));
  // Gauss points at ±1/√3 are not exact, so allow a few ulps.
  EXPECT_DOUBLE_EQ(report.total_volume, 2.0 * 6.0 * 6.0);
  EXPECT_DOUBLE_EQ(report.min_volume, 6.0);
  EXPECT_DOUBLE_EQ(report.max_volume, 6.0);
  EXPECT_EQ(report.min_quality, 1.0);
  EXPECT_EQ(report.num_inverted, 0);
}

TEST(BoxMesh, TetsArePositivelyOrientedWithExactVolume) {
  const VolumeMesh mesh = box_tet_mesh(box_min, box_max, box_cells);
  double total = 0.0;
  for (Eigen::Index e = 0; e < mesh.num_elements(); ++e) {
    TetCorners corners;
    for (int a = 0; a < 4; ++a) corners.row(a) = mesh.vertices.row(mesh.elements(e, a));
    EXPECT_EQ(tet_signed_volume(corners), 1.0) << "element " << e;
    total += tet_signed_volume(corners);
  }
  EXPECT_EQ(total, 2.0 * 6.0 * 6.0);
}

TEST(BoxMesh, TetsShareTheCellDiagonal) {
  const VolumeMesh mesh = box_tet_mesh(box_min, box_max, box_cells);
  const VolumeMesh hexes = box_hex_mesh(box_min, box_max, box_cells);
  for (Eigen::Index cell = 0; cell < hexes.num_elements(); ++cell) {
    for (Eigen::Index t = 6 * cell; t < 6 * cell + 6; ++t) {
      EXPECT_EQ(mesh.elements(t, 0), hexes.elements(cell, 0));
      EXPECT_EQ(mesh.elements(t, 3), hexes.elements(cell, 6));
    }
  }
}

TEST(BoxMesh, TetFacesConform) {
  // Every triangular face is shared by exactly two tetrahedra, except the faces on the box
  // boundary, which have one; a non-conforming split would leave interior faces with one.
  const Eigen::Vector3i cells(3, 2, 4);
  const VolumeMesh mesh = box_tet_mesh(Eigen::Vector3d::Zero(), Eigen::Vector3d(3, 2, 4), cells);
  std::map<std::array<int, 3>, int> incidence;
  for (Eigen::Index e = 0; e < mesh.num_elements(); ++e) {
    for (int skip = 0; skip < 4; ++skip) {
      std::array<int, 3> face{};
      for (int a = 0, n = 0; a < 4; ++a) {
        if (a != skip) face[n++] = mesh.elements(e, a);
      }
      std::sort(face.begin(), face.end());
      ++incidence[face];
    }
  }
  const auto on_boundary = [&](const std::array<int, 3>& face) {
    for (int axis = 0; axis < 3; ++axis) {
      for (const double side : {0.0, double(cells[axis])}) {
        if (std::all_of(face.begin(), face.end(),
                        [&](int v) { return mesh.vertices(v, axis) == side; })) {
          return true;
        }
      }
    }
    return false;
  };
  int boundary_faces = 0;
  for (const auto& [face, count] : incidence) {
    EXPECT_EQ(count, on_boundary(face) ? 1 : 2);
    boundary_faces += on_boundary(face);
  }
  EXPECT_EQ(boundary_faces, 2 * 2 * (3 * 2 + 2 * 4 + 3 * 4));
}

TEST(BoxMesh, RejectsNonPositiveCellCounts) {
  EXPECT_TRUE(throws_with_message<Error>(
      [] {
        box_hex_mesh({0, 0, 0}, {1, 1, 1}, {1, 0, 1});
      },
      "at least one cell per axis"));
  EXPECT_TRUE(throws_with_message<Error>(
      [] {
        box_tet_mesh({0, 0, 0}, {1, 1, 1}, {1, 1, -2});
      },
      "at least one cell per axis"));
}

TEST(BoxMesh, RejectsEmptyOrInvertedBox) {
  EXPECT_TRUE(throws_with_message<Error>(
      [] {
        box_hex_mesh({0, 0, 0}, {1, 0, 1}, {1, 1, 1});
      },
      "min < max in every coordinate"));
  EXPECT_TRUE(throws_with_message<Error>(
      [] {
        box_tet_mesh({0, 2, 0}, {1, 1, 1}, {1, 1, 1});
      },
      "min < max in every coordinate"));
}

TEST(BoxMesh, RejectsTooManyCells) {
  EXPECT_TRUE(throws_with_message<Error>(
      [] {
        box_tet_mesh({0, 0, 0}, {1, 1, 1}, {1024, 1024, 1024});
      },
      "too large"));
}

}  // namespace
}  // namespace khz::reduced
