#include <khz/contact/common.hpp>
#include <khz/contact/field/isosurface.hpp>
#include <khz/contact/field/mesh_distance_field.hpp>
#include <khz/contact/field/polygon_soup_field.hpp>
#include <khz/reduced/io/mesh_file.hpp>
#include <khz/reduced/mesh/mesh_report.hpp>
#include <khz/test/data_paths.hpp>
#include <khz/test/fixtures.hpp>
#include <khz/test/generated_meshes.hpp>
#include <khz/test/mesh_edits.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <numbers>
#include <random>
#include <vector>

namespace khz::contact {
namespace {

/// Generalized winding number of a closed oriented mesh around p (solid angles of its triangles,
/// Van Oosterom and Strackee's formula, over 4π): ±1 inside, 0 outside.
double winding_number(const TriangleMesh& mesh, const Eigen::Vector3d& p) {
  double total = 0.0;
  for (Eigen::Index t = 0; t < mesh.num_triangles(); ++t) {
    const Eigen::Vector3d a = mesh.vertices.row(mesh.triangles(t, 0)).transpose() - p;
    const Eigen::Vector3d b = mesh.vertices.row(mesh.triangles(t, 1)).transpose() - p;
    const Eigen::Vector3d c = mesh.vertices.row(mesh.triangles(t, 2)).transpose() - p;
    const double la = a.norm(), lb = b.norm(), lc = c.norm();
    total += 2.0 * std::atan2(a.dot(b.cross(c)),
                              la * lb * lc + a.dot(b) * lc + a.dot(c) * lb + b.dot(c) * la);
  }
  return total / (4.0 * std::numbers::pi);
}

/// The triangles of `mesh` within one connected component each (through shared vertices), as
/// separate meshes sharing the vertex matrix.
std::vector<TriangleMesh> components_of(const TriangleMesh& mesh) {
  std::vector<int> label(static_cast<std::size_t>(mesh.num_vertices()), -1);
  std::vector<std::vector<int>> adjacent(label.size());
  for (Eigen::Index t = 0; t < mesh.num_triangles(); ++t) {
    for (int c = 0; c < 3; ++c) {
      adjacent[static_cast<std::size_t>(mesh.triangles(t, c))].push_back(
          mesh.triangles(t, (c + 1) % 3));
      adjacent[static_cast<std::size_t>(mesh.triangles(t, (c + 1) % 3))].push_back(
          mesh.triangles(t, c));
    }
  }
  int count = 0;
  for (std::size_t seed = 0; seed < label.size(); ++seed) {
    if (label[seed] >= 0) continue;
    std::vector<int> stack{static_cast<int>(seed)};
    label[seed] = count;
    while (!stack.empty()) {
      const int v = stack.back();
      stack.pop_back();
      for (const int w : adjacent[static_cast<std::size_t>(v)]) {
        if (label[static_cast<std::size_t>(w)] < 0) {
          label[static_cast<std::size_t>(w)] = count;
          stack.push_back(w);
        }
      }
    }
    ++count;
  }
  std::vector<std::vector<int>> rows(static_cast<std::size_t>(count));
  for (Eigen::Index t = 0; t < mesh.num_triangles(); ++t) {
    rows[static_cast<std::size_t>(label[static_cast<std::size_t>(mesh.triangles(t, 0))])].push_back(
        static_cast<int>(t));
  }
  std::vector<TriangleMesh> parts;
  for (const std::vector<int>& triangles : rows) {
    TriangleMesh part;
    part.vertices = mesh.vertices;
    part.triangles.resize(static_cast<Eigen::Index>(triangles.size()), 3);
    for (std::size_t r = 0; r < triangles.size(); ++r) {
      part.triangles.row(static_cast<Eigen::Index>(r)) = mesh.triangles.row(triangles[r]);
    }
    parts.push_back(std::move(part));
  }
  return parts;
}

/// The closed, outward, single-component surface every soup field is signed by.
void expect_closed_outward(const TriangleMesh& surface, Eigen::Index components) {
  const reduced::MeshReport report = reduced::analyze_mesh(surface);
  EXPECT_TRUE(report.closed);
  EXPECT_TRUE(report.vertex_manifold);
  EXPECT_TRUE(report.consistently_oriented);
  EXPECT_EQ(report.num_components, components);
  EXPECT_GT(report.signed_volume, 0.0);
}

TriangleMesh scaled(TriangleMesh mesh, double factor) {
  mesh.vertices *= factor;
  return mesh;
}

PolygonSoupFieldOptions with_cells(int cells) {
  PolygonSoupFieldOptions options;
  options.field.cells = cells;
  return options;
}

TEST(PolygonSoupField, NestedSpheresKeepOnlyTheOutermostWall) {
  // Two concentric closed spheres: their σ-shells have four walls; three lie inside the outer.
  const TriangleMesh soup = test::combined(
      test::uv_sphere(32, 16), scaled(test::uv_sphere(24, 12), 0.5), Eigen::RowVector3d::Zero());
  const PolygonSoupField result = polygon_soup_field(soup, with_cells(40));
  const double h = result.field.geometry().spacing;
  EXPECT_DOUBLE_EQ(result.offset, 1.4 * h);
  EXPECT_EQ(result.components_removed, 3);
  expect_closed_outward(result.offset_surface, 1);
  // The kept wall is the outer sphere's outer one: σ beyond a polyhedron inscribed in r = 1.
  for (Eigen::Index v = 0; v < result.offset_surface.num_vertices(); ++v) {
    EXPECT_GT(result.offset_surface.vertices.row(v).norm(), 1.0);
  }
  // Everything it encloses is inside, the cavities between the spheres included.
  for (const double r : {0.0, 0.25, 0.5, 0.75, 1.0}) {
    EXPECT_LT(result.field.distance(Eigen::Vector3d(r, 0, 0)), 0.0) << r;
  }
  EXPECT_GT(result.field.distance(Eigen::Vector3d(0, 1.3, 0)), 0.0);
}

TEST(PolygonSoupField, SeparateObjectsKeepOneOuterWallEach) {
  const TriangleMesh soup = test::combined(test::uv_sphere(24, 12), test::uv_sphere(24, 12),
                                           Eigen::RowVector3d(2.6, 0, 0));
  const PolygonSoupField result = polygon_soup_field(soup, with_cells(48));
  EXPECT_EQ(result.components_removed, 2);
  expect_closed_outward(result.offset_surface, 2);
  EXPECT_LT(result.field.distance(Eigen::Vector3d(0, 0, 0)), 0.0);
  EXPECT_LT(result.field.distance(Eigen::Vector3d(2.6, 0, 0)), 0.0);
  EXPECT_GT(result.field.distance(Eigen::Vector3d(1.3, 0, 0)), 0.0);
}

TEST(PolygonSoupField, AnOpenSheetBecomesAClosedPillow) {
  // A thin structure (thesis §3.8.1, last paragraph): one closed offset surface, nothing removed.
  const PolygonSoupField result = polygon_soup_field(test::unit_square(), with_cells(40));
  EXPECT_EQ(result.components_removed, 0);
  expect_closed_outward(result.offset_surface, 1);
  const double sigma = result.offset;
  // On the sheet, σ below the pillow's faces; σ beyond them, σ above.
  // Measured −1.0000 σ and 1.0000 σ: the pillow's faces are flat.
  EXPECT_NEAR(result.field.distance(Eigen::Vector3d(0.5, 0.5, 0)), -sigma, 0.01 * sigma);
  EXPECT_NEAR(result.field.distance(Eigen::Vector3d(0.5, 0.5, 2 * sigma)), sigma, 0.01 * sigma);
}

TEST(PolygonSoupField, RejectsBadOffsetsAndSoups) {
  const TriangleMesh sphere = test::uv_sphere(16, 8);
  PolygonSoupFieldOptions options = with_cells(16);
  const double h = 1.5 * 2.0 / 16;  // the cube around [−1, 1]³, expanded 1.5 times
  options.offset = 0.9 * h;
  EXPECT_TRUE(test::throws_with_message<Error>([&] { polygon_soup_field(sphere, options); },
                                               "must exceed the grid spacing"));
  options.offset = -1.0;
  EXPECT_THROW(polygon_soup_field(sphere, options), Error);
  options.offset = 0.6;  // the margin is 0.5
  EXPECT_TRUE(test::throws_with_message<Error>([&] { polygon_soup_field(sphere, options); },
                                               "reaches the grid's boundary"));
  EXPECT_THROW(polygon_soup_field(TriangleMesh{}, {}), MeshError);
  EXPECT_THROW(polygon_soup_field(test::with_triangle(sphere, 0, 1, 999), {}), MeshError);
}

/// dino.off with ~5 % of its faces deleted, ~5 % duplicated (half of the copies reversed) and
/// ~5 % of the remaining ones reversed, in shuffled order: a polygon soup.
TriangleMesh damaged_dino(const TriangleMesh& dino) {
  std::mt19937 random(11);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  std::vector<Eigen::RowVector3i> faces;
  for (Eigen::Index t = 0; t < dino.num_triangles(); ++t) {
    const double roll = uniform(random);
    if (roll < 0.05) continue;  // deleted
    Eigen::RowVector3i face = dino.triangles.row(t);
    if (roll < 0.10) faces.push_back(uniform(random) < 0.5 ? face : face.reverse().eval());
    if (uniform(random) < 0.05) face = face.reverse().eval();
    faces.push_back(face);
  }
  std::shuffle(faces.begin(), faces.end(), random);
  TriangleMesh soup;
  soup.vertices = dino.vertices;
  soup.triangles.resize(static_cast<Eigen::Index>(faces.size()), 3);
  for (std::size_t f = 0; f < faces.size(); ++f)
    soup.triangles.row(static_cast<Eigen::Index>(f)) = faces[f];
  return soup;
}

TEST(PolygonSoupField, DamagedDinoYieldsTheSignedFieldOfItsOffsetSurface) {
  // "A soup made by deleting and duplicating faces of dino.off still yields a valid signed field
  // of its offset surface, without inside-out components."
  const TriangleMesh dino =
      reduced::read_triangle_mesh(std::filesystem::path(test::cgal_mesh_dir) / "dino.off");
  const TriangleMesh soup = damaged_dino(dino);
  const reduced::MeshReport soup_report = reduced::analyze_mesh(soup);
  ASSERT_FALSE(soup_report.closed);  // it is a soup: holes, duplicates, flipped faces
  ASSERT_FALSE(soup_report.duplicate_triangles.empty());

  const PolygonSoupField result = polygon_soup_field(soup, with_cells(64));
  const DistanceGrid& field = result.field;
  const GridGeometry& geometry = field.geometry();
  const double h = geometry.spacing, sigma = result.offset;
  EXPECT_TRUE(field.is_signed());

  // The offset surface: one closed, outward component; the inner walls went.
  expect_closed_outward(result.offset_surface, 1);
  ASSERT_GE(result.components_removed, 1);

  // Independently: the whole level set, split into components by this test; every removed one
  // is inside the kept surface (winding number 1) and faces inwards (negative volume), i.e. it
  // would have been an inside-out component.
  DistanceFieldOptions options;
  options.geometry = geometry;
  const DistanceGrid unsigned_field = unsigned_distance_field(soup, options);
  const TriangleMesh level_set = isosurface(unsigned_field, sigma);
  const std::vector<TriangleMesh> parts = components_of(level_set);
  ASSERT_EQ(static_cast<int>(parts.size()), 1 + result.components_removed);
  int outward = 0, inner = 0;
  for (const TriangleMesh& part : parts) {
    if (reduced::analyze_mesh(part).signed_volume > 0.0) {
      ++outward;
      EXPECT_EQ(part.num_triangles(), result.offset_surface.num_triangles());
      continue;
    }
    ++inner;
    const Eigen::Vector3d probe = part.vertices.row(part.triangles(0, 0)).transpose();
    EXPECT_NEAR(winding_number(result.offset_surface, probe), 1.0, 1e-6);
  }
  EXPECT_EQ(outward, 1);
  EXPECT_EQ(inner, result.components_removed);

  // Negative on the soup, about σ deep: the nearest offset point is at least σ away. The soup
  // is the ridge of the shell's distance, which trilinear interpolation flattens by up to about
  // h/2 (measured: at most σ − 0.59 h deep at the vertices, σ = 1.4 h).
  double shallowest_soup = -1e9;
  for (Eigen::Index v = 0; v < soup.num_vertices(); ++v) {
    shallowest_soup = std::max(shallowest_soup, field.distance(soup.vertices.row(v).transpose()));
  }
  EXPECT_LT(shallowest_soup, -sigma + 0.8 * h);

  // Against an independent inside/outside: the closed original's signed field. Outside the
  // dino, the signed field is U − σ (the nearest offset point lies on the way to the nearest
  // soup point); inside, the pockets the inner walls bounded are filled (negative).
  const DistanceGrid original = signed_distance_field(dino, options);
  double outer_error = 0.0, outer_squares = 0.0;
  int outer_nodes = 0, pocket_nodes = 0;
  double shallowest_pocket = -1e9;
  for (std::int64_t node = 0; node < geometry.node_count(); ++node) {
    const auto index = static_cast<std::size_t>(node);
    const double u = unsigned_field.values()[index], s = field.values()[index];
    if (original.values()[index] > 0.0 && u >= sigma + h && u <= sigma + 3 * h) {
      ++outer_nodes;
      outer_error = std::max(outer_error, std::abs(s - (u - sigma)));
      outer_squares += (s - (u - sigma)) * (s - (u - sigma));
    } else if (original.values()[index] < 0.0 && u >= sigma + h) {
      ++pocket_nodes;
      shallowest_pocket = std::max(shallowest_pocket, s);
    }
  }
  // Measured: ~10050 nodes, largest error 0.23 h (where U creases, in the soup's concave
  // corners, the level set is cut by the cells), RMS 0.051 h.
  EXPECT_GT(outer_nodes, 1000);
  EXPECT_LT(outer_error, 0.35 * h);
  EXPECT_LT(std::sqrt(outer_squares / outer_nodes), 0.08 * h);
  // Measured: 510 pocket nodes, the shallowest −3.78 h: beyond the inner wall (U ≥ σ + h) the
  // outer wall is ≥ 2σ + h = 3.8 h away. A kept inner wall would make them positive.
  EXPECT_GT(pocket_nodes, 100);
  EXPECT_LT(shallowest_pocket, -3.0 * h);

  // Positive far outside: on the box's faces and beyond.
  const double boundary = field.boundary_minimum() + h / std::sqrt(2.0);
  EXPECT_GT(boundary, 0.0);
  EXPECT_GT(field.distance(geometry.origin - Eigen::Vector3d::Constant(1.0)), 0.0);
}

}  // namespace
}  // namespace khz::contact
