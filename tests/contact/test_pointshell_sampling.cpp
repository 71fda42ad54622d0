#include <khz/contact/field/mesh_distance.hpp>
#include <khz/contact/pointshell/pointshell.hpp>
#include <khz/contact/pointshell/pointshell_sampling.hpp>
#include <khz/reduced/worker_threads.hpp>
#include <khz/test/generated_meshes.hpp>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

namespace khz::contact {
namespace {

using test::unit_cube_surface;
using test::uv_sphere;

/// The mesh with every triangle given its own three vertices, plus one vertex in no triangle.
TriangleMesh unwelded_with_stray_vertex(const TriangleMesh& mesh) {
  TriangleMesh soup;
  soup.vertices.resize(3 * mesh.num_triangles() + 1, 3);
  soup.triangles.resize(mesh.num_triangles(), 3);
  for (Eigen::Index t = 0; t < mesh.num_triangles(); ++t) {
    for (int k = 0; k < 3; ++k) {
      soup.vertices.row(3 * t + k) = mesh.vertices.row(mesh.triangles(t, k));
      soup.triangles(t, k) = static_cast<int>(3 * t + k);
    }
  }
  soup.vertices.row(3 * mesh.num_triangles()) << 5, 5, 5;
  return soup;
}

/// Rows of `points` sorted lexicographically, with the normals alongside.
std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> sorted_rows(const Pointshell& shell) {
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> rows;
  for (Eigen::Index s = 0; s < shell.size(); ++s) {
    rows.emplace_back(shell.points.row(s).transpose(), shell.normals.row(s).transpose());
  }
  std::sort(rows.begin(), rows.end(), [](const auto& a, const auto& b) {
    return std::lexicographical_compare(a.first.begin(), a.first.end(), b.first.begin(),
                                        b.first.end());
  });
  return rows;
}

double angle_between(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

TEST(VertexPointshell, CubeCornersGetTheInwardDiagonal) {
  // The angle-weighted pseudonormal does not depend on how the faces are triangulated: at a
  // cube corner it is the diagonal, although two of the three faces meet it in two triangles.
  const Pointshell shell = vertex_pointshell(unit_cube_surface());
  validate(shell);
  ASSERT_EQ(shell.size(), 8);
  EXPECT_EQ(shell.level_ends, std::vector<Eigen::Index>{8});
  for (Eigen::Index s = 0; s < 8; ++s) {
    const Eigen::Vector3d inward =
        (Eigen::Vector3d::Constant(0.5) - shell.points.row(s).transpose()).normalized();
    EXPECT_LT((shell.normals.row(s).transpose() - inward).norm(), 1e-15) << s;
  }
}

TEST(VertexPointshell, WeldsCoincidentVerticesAndSkipsUnusedOnes) {
  const TriangleMesh sphere = uv_sphere(12, 7);
  const Pointshell welded = vertex_pointshell(sphere);
  const Pointshell soup = vertex_pointshell(unwelded_with_stray_vertex(sphere));
  ASSERT_EQ(welded.size(), sphere.num_vertices());
  ASSERT_EQ(soup.size(), welded.size());
  const auto a = sorted_rows(welded);
  const auto b = sorted_rows(soup);
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].first, b[i].first);
    // Same triangles, same order of accumulation.
    EXPECT_LT((a[i].second - b[i].second).norm(), 1e-15);
  }
}

TEST(VertexPointshell, NormalsAreMeshDistancePseudonormalsAndRoughlyRadialOnASphere) {
  const TriangleMesh sphere = uv_sphere(32, 16);
  const Pointshell shell = vertex_pointshell(sphere);
  const MeshDistance distance(sphere);
  double largest_angle = 0.0;
  for (Eigen::Index s = 0; s < shell.size(); ++s) {
    const Eigen::Vector3d p = shell.points.row(s).transpose();
    const Eigen::Vector3d n = shell.normals.row(s).transpose();
    // An independent implementation of the same pseudonormal.
    EXPECT_LT((n + distance.closest(p).pseudonormal).norm(), 1e-12) << s;
    largest_angle = std::max(largest_angle, angle_between(n, -p));
  }
  // Inward and within a degree of the radius: measured 0.0060 rad (the split of each quad along
  // one diagonal tilts the fan around a ring vertex).
  EXPECT_LT(largest_angle, 0.01);
}

TEST(VertexPointshell, RejectsMeshesWithoutNormals) {
  TriangleMesh empty = unit_cube_surface();
  empty.triangles.resize(0, 3);
  EXPECT_THROW(vertex_pointshell(empty), MeshError);
  TriangleMesh flat = unit_cube_surface();
  flat.triangles.resize(1, 3);
  flat.triangles << 0, 1, 1;  // degenerate: vertices 0 and 1 have no normal
  try {
    vertex_pointshell(flat);
    FAIL() << "no exception";
  } catch (const MeshError& error) {
    EXPECT_NE(std::string(error.what()).find("vertex 0"), std::string::npos) << error.what();
  }
}

TEST(RandomPointshell, PointsLieOnTheFacesWithTheirInwardNormals) {
  const Pointshell shell = random_pointshell(unit_cube_surface(), 5000, 7);
  validate(shell);
  ASSERT_EQ(shell.size(), 5000);
  for (Eigen::Index s = 0; s < shell.size(); ++s) {
    const Eigen::Vector3d p = shell.points.row(s).transpose();
    const Eigen::Vector3d n = shell.normals.row(s).transpose();
    // The normal names the face: the inward normal of face x = 0 is +x, and so on.
    int axis = 0;
    n.cwiseAbs().maxCoeff(&axis);
    EXPECT_EQ(std::abs(n[axis]), 1.0);
    const double face = n[axis] > 0 ? 0.0 : 1.0;
    EXPECT_LT(std::abs(p[axis] - face), 1e-15) << s;
    EXPECT_GE(p.minCoeff(), -1e-15);
    EXPECT_LE(p.maxCoeff(), 1.0 + 1e-15);
  }
}

TEST(RandomPointshell, IsUniformByArea) {
  // Two triangles, areas 1/2 and 3/2: a quarter of the points on the first. And uniform within
  // a triangle: the mean point is the centroid.
  TriangleMesh mesh;
  mesh.vertices.resize(6, 3);
  mesh.vertices << 0, 0, 0, 1, 0, 0, 0, 1, 0,  //
      0, 0, 1, 3, 0, 1, 0, 1, 1;
  mesh.triangles.resize(2, 3);
  mesh.triangles << 0, 1, 2, 3, 4, 5;
  const Eigen::Index count = 40000;
  const Pointshell shell = random_pointshell(mesh, count, 3);
  Eigen::Index first = 0;
  Eigen::Vector3d mean[2] = {Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()};
  for (Eigen::Index s = 0; s < count; ++s) {
    const bool on_first = shell.points(s, 2) == 0.0;
    first += on_first;
    mean[on_first ? 0 : 1] += shell.points.row(s).transpose();
  }
  // Binomial: σ = √(n p (1−p)) ≈ 87 points; 4σ.
  EXPECT_NEAR(static_cast<double>(first), 0.25 * count, 4 * std::sqrt(count * 0.25 * 0.75));
  mean[0] /= static_cast<double>(first);
  mean[1] /= static_cast<double>(count - first);
  // Coordinates on a triangle have σ ≤ 0.71 (legs 1 and 3); the mean of n has σ/√n; 4σ.
  EXPECT_LT((mean[0] - Eigen::Vector3d(1.0 / 3, 1.0 / 3, 0)).norm(), 4 * 0.25 / std::sqrt(1e4));
  EXPECT_LT((mean[1] - Eigen::Vector3d(1.0, 1.0 / 3, 1)).norm(), 4 * 0.71 / std::sqrt(3e4));
}

TEST(RandomPointshell, IsReproducibleForASeedOnAnyThreadCount) {
  const TriangleMesh sphere = uv_sphere(16, 8);
  const Pointshell a = random_pointshell(sphere, 3000, 11);
  const Pointshell b = [&] {
    const reduced::ScopedWorkerThreads one(1);
    return random_pointshell(sphere, 3000, 11);
  }();
  EXPECT_EQ(a.points, b.points);
  EXPECT_EQ(a.normals, b.normals);
  const Pointshell c = random_pointshell(sphere, 3000, 12);
  EXPECT_NE(a.points, c.points);
  // Point k depends on (seed, k) only: a shorter run is a prefix.
  const Pointshell d = random_pointshell(sphere, 100, 11);
  EXPECT_EQ(d.points, a.points.topRows(100));
}

TEST(RandomPointshell, RejectsBadArguments) {
  EXPECT_THROW(random_pointshell(unit_cube_surface(), 0), Error);
  TriangleMesh flat = unit_cube_surface();
  flat.triangles.resize(1, 3);
  flat.triangles << 0, 1, 1;
  EXPECT_THROW(random_pointshell(flat, 10), Error);
  TriangleMesh bad = unit_cube_surface();
  bad.triangles(0, 0) = 8;
  EXPECT_THROW(random_pointshell(bad, 10), MeshError);
}

TEST(VoxelPointshell, CentresOfTheCellsTouchingTheSurface) {
  const TriangleMesh sphere = uv_sphere(48, 24);
  const double h = 0.1;
  const Pointshell shell = voxel_pointshell(sphere, h);
  validate(shell);
  const MeshDistance distance(sphere);
  const double half_diagonal = h * std::sqrt(3.0) / 2;
  const Eigen::Vector3d origin = shell.points.row(0).transpose();
  double farthest = 0.0;
  for (Eigen::Index s = 0; s < shell.size(); ++s) {
    const Eigen::Vector3d p = shell.points.row(s).transpose();
    // On one lattice of spacing h (cell centres).
    const Eigen::Vector3d steps = (p - origin) / h;
    EXPECT_LT((steps - steps.array().round().matrix()).norm(), 1e-9) << s;
    const ClosestPoint closest = distance.closest(p);
    farthest = std::max(farthest, closest.distance);
    EXPECT_LT((shell.normals.row(s).transpose() + closest.pseudonormal).norm(), 1e-15);
  }
  // A touching cell's centre is within half a cell diagonal of the surface.
  EXPECT_LE(farthest, half_diagonal * (1 + 1e-12));
  // Conversely every surface point is in a touching cell: a vertex is within half a diagonal
  // of some centre.
  for (Eigen::Index v = 0; v < sphere.num_vertices(); ++v) {
    const double nearest =
        (shell.points.rowwise() - sphere.vertices.row(v)).rowwise().norm().minCoeff();
    EXPECT_LE(nearest, half_diagonal * (1 + 1e-12)) << v;
  }
  // A shell of cells about one cell thick around the unit sphere: 4π/h² · (1 … 3) cells.
  EXPECT_GT(shell.size(), 4 * std::numbers::pi / (h * h));
  EXPECT_LT(shell.size(), 3 * 4 * std::numbers::pi / (h * h));
}

TEST(VoxelPointshell, RejectsBadCellSizes) {
  EXPECT_THROW(voxel_pointshell(unit_cube_surface(), 0.0), Error);
  EXPECT_THROW(voxel_pointshell(unit_cube_surface(), -1.0), Error);
  EXPECT_THROW(voxel_pointshell(unit_cube_surface(), std::nan("")), Error);
  EXPECT_THROW(voxel_pointshell(unit_cube_surface(), 1e-4), Error);  // 10⁴ cells per side
}

TEST(InwardNormals, ReportsProgressAndCancels) {
  const TriangleMesh sphere = uv_sphere(16, 8);
  const MeshDistance distance(sphere);
  const Pointshell points = random_pointshell(sphere, 10000, 1);
  std::vector<std::int64_t> done;
  const PointMatrix normals = inward_normals(distance, points.points, [&](const Progress& p) {
    EXPECT_EQ(p.stage, "pointshell normals");
    EXPECT_EQ(p.total, 10000);
    done.push_back(p.done);
    return true;
  });
  ASSERT_GE(done.size(), 3u);
  EXPECT_EQ(done.front(), 0);
  EXPECT_EQ(done.back(), 10000);
  EXPECT_TRUE(std::is_sorted(done.begin(), done.end()));
  // Points drawn inside faces get the face normal, the sampler's own normal.
  EXPECT_LT((normals - points.normals).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_THROW(inward_normals(distance, points.points, [](const Progress&) { return false; }),
               Cancelled);
  PointMatrix bad = points.points;
  bad(5, 1) = std::nan("");
  EXPECT_THROW(inward_normals(distance, bad), Error);
}

}  // namespace
}  // namespace khz::contact
