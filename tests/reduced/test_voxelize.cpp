#include <khz/reduced/errors.hpp>
#include <khz/reduced/io/mesh_file.hpp>
#include <khz/reduced/mesh/element_quality.hpp>
#include <khz/reduced/meshing/voxelize.hpp>
#include <khz/test/fixtures.hpp>
#include <khz/test/generated_meshes.hpp>

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <set>

namespace khz::reduced {
namespace {

using test::throws_with_message;
using test::unit_cube_surface;

VolumeMesh voxelize_with(const TriangleMesh& soup, int resolution, double enlargement,
                         bool fill_interior = false) {
  VoxelizeOptions options;
  options.resolution = resolution;
  options.enlargement = enlargement;
  options.fill_interior = fill_interior;
  return voxelize(soup, options);
}

TriangleMesh single_triangle(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                             const Eigen::Vector3d& c) {
  TriangleMesh mesh;
  mesh.vertices.resize(3, 3);
  mesh.vertices << a.transpose(), b.transpose(), c.transpose();
  mesh.triangles.resize(1, 3);
  mesh.triangles << 0, 1, 2;
  return mesh;
}

/// Lowest corner of every element, in voxel units of size h from `origin`, rounded.
std::set<std::array<long, 3>> voxel_cells(const VolumeMesh& mesh, const Eigen::Vector3d& origin,
                                          double h) {
  std::set<std::array<long, 3>> cells;
  for (Eigen::Index e = 0; e < mesh.num_elements(); ++e) {
    const Eigen::Vector3d p = (mesh.vertices.row(mesh.elements(e, 0)).transpose() - origin) / h;
    cells.insert({std::lround(p.x()), std::lround(p.y()), std::lround(p.z())});
  }
  return cells;
}

// Unit cube, default enlargement 1.2 at resolution 10: the grid is [−0.1, 1.1]³ with h = 0.12,
// so the cube's faces lie at voxel coordinates 0.83 and 9.17, inside the first and last voxel
// layers. The surface touches exactly the voxels with some index 0 or 9: 10³ − 8³.
TEST(Voxelize, CubeShellAtDefaultEnlargement) {
  const VolumeMesh mesh = voxelize_with(unit_cube_surface(), 10, 1.2);
  EXPECT_EQ(mesh.num_elements(), 1000 - 512);
  // Lattice points strictly inside the shell, (2..8)³, belong to interior voxels only.
  EXPECT_EQ(mesh.num_vertices(), 11 * 11 * 11 - 7 * 7 * 7);
}

TEST(Voxelize, CubeFilledAtDefaultEnlargement) {
  const VolumeMesh mesh = voxelize_with(unit_cube_surface(), 10, 1.2, true);
  EXPECT_EQ(mesh.num_elements(), 1000);
  EXPECT_EQ(mesh.num_vertices(), 11 * 11 * 11);
}

// With enlargement 2 the grid is [−0.5, 1.5]³, h = 0.2: the faces lie at voxel coordinates 2.5
// and 7.5, so the cube covers voxels 2..7 per axis; its shell is 6³ − 4³ voxels.
TEST(Voxelize, CubeShellWithMargin) {
  const VolumeMesh mesh = voxelize_with(unit_cube_surface(), 10, 2.0);
  EXPECT_EQ(mesh.num_elements(), 6 * 6 * 6 - 4 * 4 * 4);
  EXPECT_EQ(mesh.num_vertices(), 7 * 7 * 7 - 3 * 3 * 3);
}

TEST(Voxelize, CubeFilledWithMargin) {
  const VolumeMesh mesh = voxelize_with(unit_cube_surface(), 10, 2.0, true);
  EXPECT_EQ(mesh.num_elements(), 6 * 6 * 6);
  EXPECT_EQ(mesh.num_vertices(), 7 * 7 * 7);
  EXPECT_EQ(voxel_cells(mesh, Eigen::Vector3d::Constant(-0.5), 0.2).begin()->at(0), 2);
}

TEST(Voxelize, VoxelsAreEqualPositiveCubesWithSharedVertices) {
  const VolumeMesh mesh = voxelize_with(unit_cube_surface(), 10, 2.0, true);
  EXPECT_EQ(mesh.element_type, ElementType::hexahedron);
  EXPECT_EQ(mesh.element_groups.size(), 0);
  const QualityReport report = analyze_elements(mesh);
  EXPECT_EQ(report.num_inverted + report.num_degenerate, 0);
  EXPECT_NEAR(report.min_quality, 1.0, 1e-12);
  EXPECT_NEAR(report.min_volume, 0.008, 1e-15);
  EXPECT_NEAR(report.max_volume, 0.008, 1e-15);
  EXPECT_NEAR(report.total_volume, 216 * 0.008, 1e-12);
}

// A triangle with a sloped edge, so the exact test keeps fewer voxels than its bounding box.
// Extents (1, 0.5, 0), enlargement 1.2, resolution 9: h = 0.1333, origin (−0.1, −0.35, −0.6).
// In voxel coordinates the triangle is {x ≥ 0.75, y ≥ 2.625, x + 2y ≤ 13.5} in the plane
// z = 4.5. Voxel (i, j, 4) touches it iff j ∈ [2, 6] and max(i, 0.75) + 2·max(j, 2.625) ≤ 13.5:
// 9 + 8 + 6 + 4 + 2 voxels for j = 2..6 (its bounding box touches 9·5).
TEST(Voxelize, SingleTriangleKeepsExactlyTheVoxelsItTouches) {
  const VolumeMesh mesh = voxelize_with(single_triangle({0, 0, 0}, {1, 0, 0}, {0, 0.5, 0}), 9, 1.2);
  EXPECT_EQ(mesh.num_elements(), 29);
  const double h = 1.2 / 9;
  std::set<std::array<long, 3>> expected;
  for (long j = 2; j <= 6; ++j) {
    for (long i = 0; i < 9; ++i) {
      if (std::max(double(i), 0.75) + 2 * std::max(double(j), 2.625) <= 13.5) {
        expected.insert({i, j, 4});
      }
    }
  }
  EXPECT_EQ(voxel_cells(mesh, Eigen::Vector3d(-0.1, -0.35, -0.6), h), expected);
}

// A degenerate triangle is the segment it spans: (0,0,0)–(1,0,0) with enlargement 1.5 at
// resolution 3 (h = 0.5) runs from voxel coordinate 0.5 to 2.5 along the row y = z = 1.5.
TEST(Voxelize, DegenerateTriangleIsVoxelizedAsASegment) {
  const VolumeMesh mesh = voxelize_with(single_triangle({0, 0, 0}, {1, 0, 0}, {1, 0, 0}), 3, 1.5);
  const std::set<std::array<long, 3>> expected = {{0, 1, 1}, {1, 1, 1}, {2, 1, 1}};
  EXPECT_EQ(voxel_cells(mesh, Eigen::Vector3d(-0.25, -0.75, -0.75), 0.5), expected);
  EXPECT_EQ(mesh.num_vertices(), 4 * 2 * 2);
}

TEST(Voxelize, OpenSurfaceEnclosesNothing) {
  const VolumeMesh shell = voxelize_with(test::unit_square(), 16, 1.2);
  const VolumeMesh filled = voxelize_with(test::unit_square(), 16, 1.2, true);
  EXPECT_GT(shell.num_elements(), 0);
  EXPECT_EQ(filled.elements, shell.elements);
  EXPECT_EQ(filled.vertices, shell.vertices);
}

TEST(Voxelize, ResolutionOneGivesOneVoxel) {
  const VolumeMesh mesh = voxelize_with(unit_cube_surface(), 1, 1.0);
  EXPECT_EQ(mesh.num_elements(), 1);
  EXPECT_EQ(mesh.vertices.colwise().minCoeff(), Eigen::RowVector3d(0, 0, 0));
  EXPECT_EQ(mesh.vertices.colwise().maxCoeff(), Eigen::RowVector3d(1, 1, 1));
}

// Independent of the separating-axis test: every vertex and triangle centroid of the dragon
// must lie in (or on) the axis-aligned box of some kept voxel.
TEST(Voxelize, DragonSurfaceIsCoveredByVoxels) {
  const TriangleMesh dragon = read_triangle_mesh(test::cgal_mesh("ChineseDragon-10kv.off"));
  const VolumeMesh mesh = voxelize_with(dragon, 64, 1.2);
  ASSERT_GT(mesh.num_elements(), 0);
  const Eigen::Vector3d origin = mesh.vertices.colwise().minCoeff().transpose();
  const Eigen::Index corner = mesh.elements(0, 6);
  const double h = mesh.vertices(corner, 0) - mesh.vertices(mesh.elements(0, 0), 0);
  const std::set<std::array<long, 3>> cells = voxel_cells(mesh, origin, h);
  const auto covered = [&](const Eigen::Vector3d& x) {
    const Eigen::Vector3d p = (x - origin) / h;
    const double slack = 1e-9;  // points on a voxel face may round to either side
    for (long i = std::lround(std::floor(p.x() - slack));
         i <= std::lround(std::floor(p.x() + slack)); ++i) {
      for (long j = std::lround(std::floor(p.y() - slack));
           j <= std::lround(std::floor(p.y() + slack)); ++j) {
        for (long k = std::lround(std::floor(p.z() - slack));
             k <= std::lround(std::floor(p.z() + slack)); ++k) {
          if (cells.contains({i, j, k})) return true;
        }
      }
    }
    return false;
  };
  for (Eigen::Index v = 0; v < dragon.num_vertices(); ++v) {
    EXPECT_TRUE(covered(dragon.vertices.row(v).transpose())) << "vertex " << v;
  }
  for (Eigen::Index t = 0; t < dragon.num_triangles(); ++t) {
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    for (int k = 0; k < 3; ++k)
      centroid += dragon.vertices.row(dragon.triangles(t, k)).transpose() / 3;
    EXPECT_TRUE(covered(centroid)) << "triangle " << t;
  }
}

TEST(Voxelize, DragonVoxelsArePositivelyOrientedCubes) {
  // Node a of every element sits at node 0 + h·(VTK corner offset a): an axis-aligned cube in
  // positive node order. (Cheaper in Debug than analyze_elements() on 10⁴ hexahedra.)
  const TriangleMesh dragon = read_triangle_mesh(test::cgal_mesh("ChineseDragon-10kv.off"));
  const VolumeMesh mesh = voxelize_with(dragon, 64, 1.2);
  const double h = mesh.vertices(mesh.elements(0, 1), 0) - mesh.vertices(mesh.elements(0, 0), 0);
  const Eigen::Matrix<double, 8, 3, Eigen::RowMajor> offsets =
      (Eigen::Matrix<double, 8, 3, Eigen::RowMajor>() << 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0, 0,
       1, 1, 0, 1, 1, 1, 1, 0, 1, 1)
          .finished();
  EXPECT_GT(h, 0.0);
  for (Eigen::Index e = 0; e < mesh.num_elements(); ++e) {
    const Eigen::RowVector3d base = mesh.vertices.row(mesh.elements(e, 0));
    for (int a = 1; a < 8; ++a) {
      const Eigen::RowVector3d expected = base + h * offsets.row(a);
      ASSERT_LT((mesh.vertices.row(mesh.elements(e, a)) - expected).norm(), 1e-9 * h)
          << "element " << e << " node " << a;
    }
  }
}

TEST(Voxelize, RejectsResolutionOutOfRange) {
  EXPECT_TRUE(throws_with_message<Error>([] { voxelize_with(unit_cube_surface(), 0, 1.2); },
                                         "resolution must be in [1, 1024], got 0"));
  EXPECT_TRUE(throws_with_message<Error>([] { voxelize_with(unit_cube_surface(), 1025, 1.2); },
                                         "resolution must be in [1, 1024], got 1025"));
}

TEST(Voxelize, RejectsEnlargementBelowOne) {
  EXPECT_TRUE(throws_with_message<Error>([] { voxelize_with(unit_cube_surface(), 8, 0.9); },
                                         "enlargement must be a finite number >= 1"));
  EXPECT_TRUE(throws_with_message<Error>([] { voxelize_with(unit_cube_surface(), 8, NAN); },
                                         "enlargement must be a finite number >= 1"));
}

TEST(Voxelize, RejectsEmptyMesh) {
  EXPECT_TRUE(throws_with_message<Error>([] { voxelize(TriangleMesh{}); }, "no triangles"));
}

TEST(Voxelize, RejectsMeshWithoutExtent) {
  EXPECT_TRUE(throws_with_message<Error>(
      [] {
        voxelize(single_triangle({1, 2, 3}, {1, 2, 3}, {1, 2, 3}));
      },
      "no extent"));
}

TEST(Voxelize, RejectsInvalidMesh) {
  TriangleMesh mesh = unit_cube_surface();
  mesh.triangles(4, 1) = 99;
  EXPECT_TRUE(throws_with_message<MeshError>([&] { voxelize(mesh); }, "triangle 4"));
}

}  // namespace
}  // namespace khz::reduced
