#include <khz/contact/common.hpp>
#include <khz/contact/field/distance_grid.hpp>
#include <khz/contact/field/isosurface.hpp>
#include <khz/reduced/mesh/mesh_report.hpp>
#include <khz/reduced/worker_threads.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <numbers>
#include <utility>

namespace khz::contact {
namespace {

using Field = std::function<double(const Eigen::Vector3d&)>;

/// A grid over [−1, 1]³ sampling `f` at its nodes.
DistanceGrid sampled(int cells, const Field& f) {
  const GridGeometry geometry{Eigen::Vector3d(-1, -1, -1), 2.0 / cells, cells};
  std::vector<float> values(static_cast<std::size_t>(geometry.node_count()));
  for (int k = 0; k <= cells; ++k) {
    for (int j = 0; j <= cells; ++j) {
      for (int i = 0; i <= cells; ++i) {
        values[static_cast<std::size_t>(geometry.node_index(i, j, k))] =
            static_cast<float>(f(geometry.node_position(i, j, k)));
      }
    }
  }
  return DistanceGrid(geometry, std::move(values), true);
}

double sphere(const Eigen::Vector3d& p) { return p.norm() - 0.6; }

constexpr double kMajorRadius = 0.55, kMinorRadius = 0.25;
double torus(const Eigen::Vector3d& p) {
  return std::hypot(std::hypot(p.x(), p.y()) - kMajorRadius, p.z()) - kMinorRadius;
}

double box(const Eigen::Vector3d& p) {
  const Eigen::Vector3d q = p.cwiseAbs() - Eigen::Vector3d(0.7, 0.5, 0.3);
  return q.cwiseMax(0.0).norm() + std::min(q.maxCoeff(), 0.0);
}

Eigen::Vector3d corner(const TriangleMesh& mesh, Eigen::Index t, int c) {
  return mesh.vertices.row(mesh.triangles(t, c)).transpose();
}

Eigen::Vector3d area_normal(const TriangleMesh& mesh, Eigen::Index t) {
  return 0.5 *
         (corner(mesh, t, 1) - corner(mesh, t, 0)).cross(corner(mesh, t, 2) - corner(mesh, t, 0));
}

/// Every directed edge used once and its reverse used once: closed, edge-manifold and
/// consistently oriented, counted independently of analyze_mesh().
bool every_edge_has_one_opposite_twin(const TriangleMesh& mesh) {
  std::map<std::pair<int, int>, int> uses;
  for (Eigen::Index t = 0; t < mesh.num_triangles(); ++t) {
    for (int c = 0; c < 3; ++c) ++uses[{mesh.triangles(t, c), mesh.triangles(t, (c + 1) % 3)}];
  }
  for (const auto& [edge, count] : uses) {
    const auto twin = uses.find({edge.second, edge.first});
    if (count != 1 || twin == uses.end() || twin->second != 1) return false;
  }
  return true;
}

/// The smallest ratio 2·area / longest edge² over the triangles (0 for a degenerate one).
double least_shape_ratio(const TriangleMesh& mesh) {
  double least = std::numeric_limits<double>::infinity();
  for (Eigen::Index t = 0; t < mesh.num_triangles(); ++t) {
    const Eigen::Vector3d a = corner(mesh, t, 0), b = corner(mesh, t, 1), c = corner(mesh, t, 2);
    const double longest2 =
        std::max({(b - a).squaredNorm(), (c - b).squaredNorm(), (a - c).squaredNorm()});
    least = std::min(least, 2.0 * area_normal(mesh, t).norm() / longest2);
  }
  return least;
}

/// What every closed level set of a signed field must satisfy. `least_cosine_bound`: bound on
/// the cosine between a triangle's normal and the field's gradient at its centroid.
void expect_closed_and_outward(const TriangleMesh& mesh, const Field& f, Eigen::Index euler,
                               double least_cosine_bound) {
  ASSERT_GT(mesh.num_triangles(), 0);
  const reduced::MeshReport report = reduced::analyze_mesh(mesh);
  EXPECT_TRUE(report.closed);
  EXPECT_TRUE(report.vertex_manifold);
  EXPECT_TRUE(report.consistently_oriented);
  EXPECT_TRUE(every_edge_has_one_opposite_twin(mesh));
  EXPECT_EQ(report.euler_characteristic, euler);
  EXPECT_EQ(report.num_components, 1);
  EXPECT_GT(report.signed_volume, 0.0);
  // Not degenerate: vertices stay 10⁻⁶ of an edge off the nodes, so the thinnest slivers (two
  // vertices near one node, the third an edge away) have a ratio ~10⁻⁶ (measured ≥ 5e-7);
  // collinear vertices would give ~10⁻¹⁶. (Triangles around a nudged node are ~10⁻⁶ h small,
  // under analyze_mesh()'s absolute area threshold, hence this scale-free check.)
  EXPECT_GT(least_shape_ratio(mesh), 1e-7);
  EXPECT_EQ(report.num_duplicate_vertices, 0);  // shared edges share their vertex
  EXPECT_EQ(report.num_unreferenced_vertices, 0);

  // Each triangle faces along the field's gradient (central differences of f at its centroid).
  double least_cosine = 1.0;
  for (Eigen::Index t = 0; t < mesh.num_triangles(); ++t) {
    const Eigen::Vector3d centroid =
        (corner(mesh, t, 0) + corner(mesh, t, 1) + corner(mesh, t, 2)) / 3.0;
    Eigen::Vector3d gradient;
    for (int axis = 0; axis < 3; ++axis) {
      const Eigen::Vector3d step = 1e-6 * Eigen::Vector3d::Unit(axis);
      gradient[axis] = (f(centroid + step) - f(centroid - step)) / 2e-6;
    }
    least_cosine =
        std::min(least_cosine, area_normal(mesh, t).normalized().dot(gradient.normalized()));
  }
  EXPECT_GT(least_cosine, least_cosine_bound);
}

double area(const TriangleMesh& mesh) {
  double total = 0.0;
  for (Eigen::Index t = 0; t < mesh.num_triangles(); ++t) total += area_normal(mesh, t).norm();
  return total;
}

TEST(Isosurface, SphereIsAClosedOutwardGenusZeroSurfaceOnTheLevel) {
  const int cells = 40;
  const double h = 2.0 / cells;
  const DistanceGrid grid = sampled(cells, sphere);
  const TriangleMesh mesh = isosurface(grid, 0.0);
  // Nodes such as (0.6, 0, 0) lie exactly on this sphere; the triangles nudged off them face
  // like the tetrahedra's faces near the node (measured least cosine 1/3).
  expect_closed_and_outward(mesh, sphere, 2, 0.25);

  // Vertices sit where the edge's linear interpolant meets the level: exactly on the trilinear
  // interpolant along grid lines, within its O(h²) departure from linearity along the diagonals;
  // and within O(h²) of the sphere.
  double trilinear_error = 0.0, surface_error = 0.0;
  for (Eigen::Index v = 0; v < mesh.num_vertices(); ++v) {
    const Eigen::Vector3d p = mesh.vertices.row(v).transpose();
    trilinear_error = std::max(trilinear_error, std::abs(grid.distance(p)));
    surface_error = std::max(surface_error, std::abs(sphere(p)));
  }
  // Measured 0.0203 h and 0.0297 h at 40 cells (h²/r-sized: h/r = 1/12).
  EXPECT_LT(trilinear_error, 0.03 * h);
  EXPECT_LT(surface_error, 0.045 * h);
  // Measured 0.9016 (0.35 % small: the facets cut inside the sphere).
  EXPECT_NEAR(reduced::analyze_mesh(mesh).signed_volume, 4.0 / 3.0 * std::numbers::pi * 0.216,
              0.0045);
}

TEST(Isosurface, TorusHasEulerCharacteristicZero) {
  const TriangleMesh mesh = isosurface(sampled(48, torus), 0.0);
  expect_closed_and_outward(mesh, torus, 0, 0.9);  // measured 0.987
}

TEST(Isosurface, BoxWithSharpEdges) {
  const TriangleMesh mesh = isosurface(sampled(32, box), 0.0);
  // Faces on node planes (nudging everywhere); the gradient at a centroid inside an edge's
  // chamfer can be a neighbouring face's normal, perpendicular to the chamfer (measured 0):
  // no triangle faces against it.
  expect_closed_and_outward(mesh, box, 2, -1e-9);
}

TEST(Isosurface, PositiveLevelsAreOffsetSurfaces) {
  // The level 0.2 of the torus's field is a fatter torus.
  const auto fat = [](const Eigen::Vector3d& p) { return torus(p) - 0.2; };
  const TriangleMesh mesh = isosurface(sampled(48, torus), 0.2);
  expect_closed_and_outward(mesh, fat, 0, 0.9);  // measured 0.974
}

TEST(Isosurface, AreaConvergesToTheAnalyticArea) {
  const double sphere_area = 4.0 * std::numbers::pi * 0.36;
  const double torus_area = 4.0 * std::numbers::pi * std::numbers::pi * kMajorRadius * kMinorRadius;
  double sphere_errors[3], torus_errors[3];
  for (int level = 0; level < 3; ++level) {
    const int cells = 16 << level;
    sphere_errors[level] = std::abs(area(isosurface(sampled(cells, sphere), 0.0)) - sphere_area);
    torus_errors[level] = std::abs(area(isosurface(sampled(cells, torus), 0.0)) - torus_area);
  }
  // Second-order convergence (the vertices are O(h²) off the surface, the facet normals O(h)
  // off its normals): measured relative errors sphere 1.1 %, 0.28 %, 0.070 %; torus 1.2 %,
  // 0.30 %, 0.073 %, i.e. ratios 4.0 per halving.
  for (int level = 0; level + 1 < 3; ++level) {
    EXPECT_GT(sphere_errors[level] / sphere_errors[level + 1], 3.5) << level;
    EXPECT_GT(torus_errors[level] / torus_errors[level + 1], 3.5) << level;
  }
  EXPECT_LT(sphere_errors[2] / sphere_area, 1e-3);
  EXPECT_LT(torus_errors[2] / torus_area, 1e-3);
}

TEST(Isosurface, InvertedFieldGivesInwardTriangles) {
  // Counter-clockwise seen from the larger side: for −d that is the inside.
  const TriangleMesh mesh =
      isosurface(sampled(24, [](const Eigen::Vector3d& p) { return -sphere(p); }), 0.0);
  const reduced::MeshReport report = reduced::analyze_mesh(mesh);
  EXPECT_TRUE(report.closed);
  EXPECT_TRUE(report.consistently_oriented);
  EXPECT_LT(report.signed_volume, 0.0);
}

TEST(Isosurface, NodesExactlyOnTheLevelAreNudgedToTheLargerSide) {
  // An L∞ ball with integer node values: a whole shell of nodes lies exactly on level 0.
  const int cells = 12;
  const auto cube = [&](const Eigen::Vector3d& p) {
    return std::round(p.cwiseAbs().maxCoeff() * cells / 2.0) - 3.0;
  };
  const DistanceGrid grid = sampled(cells, cube);
  const TriangleMesh mesh = isosurface(grid, 0.0);
  const reduced::MeshReport report = reduced::analyze_mesh(mesh);
  EXPECT_TRUE(report.closed);
  EXPECT_TRUE(report.vertex_manifold);
  EXPECT_TRUE(report.consistently_oriented);
  EXPECT_EQ(report.euler_characteristic, 2);
  EXPECT_EQ(report.num_duplicate_vertices, 0);
  EXPECT_GT(least_shape_ratio(mesh), 1e-7);
  // The nodes at the level count as outside: the surface runs just inside them, between the
  // values −1 and 0, a hair from the level-0 nodes.
  const double h = 2.0 / cells;
  for (Eigen::Index v = 0; v < mesh.num_vertices(); ++v) {
    const double linf = mesh.vertices.row(v).cwiseAbs().maxCoeff();
    EXPECT_LT(linf, 3 * h);
    EXPECT_GT(linf, 3 * h - 1e-5 * h);
  }
}

TEST(Isosurface, OpenWhereTheLevelSetLeavesTheBox) {
  // A tilted plane: the boundary of the mesh lies on the box's faces, and nowhere else.
  const Eigen::Vector3d normal = Eigen::Vector3d(0.3, -0.5, 1.0).normalized();
  const DistanceGrid grid = sampled(10, [&](const Eigen::Vector3d& p) { return normal.dot(p); });
  const TriangleMesh mesh = isosurface(grid, 0.1);
  std::map<std::pair<int, int>, int> uses;
  for (Eigen::Index t = 0; t < mesh.num_triangles(); ++t) {
    for (int c = 0; c < 3; ++c) {
      const int a = mesh.triangles(t, c), b = mesh.triangles(t, (c + 1) % 3);
      ++uses[{std::min(a, b), std::max(a, b)}];
    }
    EXPECT_GT(area_normal(mesh, t).dot(normal), 0.0);
  }
  int boundary = 0;
  for (const auto& [edge, count] : uses) {
    ASSERT_LE(count, 2);
    if (count == 2) continue;
    ++boundary;
    for (const int v : {edge.first, edge.second}) {
      EXPECT_NEAR(mesh.vertices.row(v).cwiseAbs().maxCoeff(), 1.0, 1e-12);
    }
  }
  EXPECT_GT(boundary, 0);
  // Linear fields are reproduced exactly: every vertex is on the plane (float node values).
  for (Eigen::Index v = 0; v < mesh.num_vertices(); ++v) {
    EXPECT_NEAR(normal.dot(mesh.vertices.row(v).transpose()), 0.1, 1e-6);
  }
}

TEST(Isosurface, EmptyWhenTheLevelDoesNotCross) {
  const DistanceGrid grid = sampled(8, sphere);
  for (const double level : {-0.7, 5.0}) {  // below every node, above every node
    const TriangleMesh mesh = isosurface(grid, level);
    EXPECT_EQ(mesh.num_vertices(), 0);
    EXPECT_EQ(mesh.num_triangles(), 0);
    EXPECT_EQ(mesh.triangles.cols(), 3);
  }
  EXPECT_THROW(isosurface(grid, std::numeric_limits<double>::quiet_NaN()), Error);
}

TEST(Isosurface, OutputDoesNotDependOnTheThreadCount) {
  const DistanceGrid grid = sampled(40, torus);
  reduced::ScopedWorkerThreads threads(1);
  const TriangleMesh serial = isosurface(grid, 0.05);
  reduced::set_worker_threads(3);
  const TriangleMesh parallel = isosurface(grid, 0.05);
  EXPECT_EQ(serial.vertices, parallel.vertices);
  EXPECT_EQ(serial.triangles, parallel.triangles);
}

}  // namespace
}  // namespace khz::contact
