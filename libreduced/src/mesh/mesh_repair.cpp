#include <khz/reduced/errors.hpp>
#include <khz/reduced/mesh/mesh_repair.hpp>
#include <khz/reduced/mesh/mesh_report.hpp>

#include "mesh/mesh_defects.hpp"
#include "mesh/union_find.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/connected_components.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/orientation.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/boost/graph/helpers.h>
#include <CGAL/boost/graph/iterator.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <string>
#include <vector>

namespace khz::reduced {
namespace {

namespace pmp = CGAL::Polygon_mesh_processing;
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Polygon = std::array<std::size_t, 3>;

/// For each vertex, the lowest-indexed vertex of its cluster, clusters being the connected
/// groups of vertices within `tolerance` (> 0) of each other. A uniform grid of cells at least
/// `tolerance` wide means only vertices in neighbouring cells need comparing.
std::vector<Eigen::Index> nearby_representatives(const VertexMatrix& vertices, double tolerance) {
  using Cell = std::array<std::int64_t, 3>;
  struct Entry {
    Cell cell;
    Eigen::Index vertex;
    auto operator<=>(const Entry&) const = default;
  };
  detail::UnionFind clusters(vertices.rows());
  if (vertices.rows() > 0) {
    const Eigen::RowVector3d low = vertices.colwise().minCoeff();
    const double extent = (vertices.colwise().maxCoeff() - low).maxCoeff();
    // Widened when the tolerance is tiny against the extent, so cell coordinates fit in 64 bits.
    const double width = std::max(tolerance, extent * 0x1p-52);
    std::vector<Entry> entries;
    entries.reserve(vertices.rows());
    for (Eigen::Index v = 0; v < vertices.rows(); ++v) {
      const Eigen::RowVector3d scaled = ((vertices.row(v) - low) / width).array().floor();
      entries.push_back(
          {{std::int64_t(scaled.x()), std::int64_t(scaled.y()), std::int64_t(scaled.z())}, v});
    }
    std::sort(entries.begin(), entries.end());
    const auto cell_less = [](const Entry& a, const Entry& b) { return a.cell < b.cell; };
    for (auto begin = entries.begin(); begin != entries.end();) {
      const auto end = std::upper_bound(begin, entries.end(), *begin, cell_less);
      for (int n = 0; n < 27; ++n) {
        Entry probe = *begin;
        for (int c = 0, code = n; c < 3; ++c, code /= 3) probe.cell[c] += code % 3 - 1;
        const auto [first, last] =
            std::equal_range(entries.begin(), entries.end(), probe, cell_less);
        for (auto a = begin; a != end; ++a) {
          for (auto b = first; b != last; ++b) {
            if (a->vertex < b->vertex &&
                (vertices.row(a->vertex) - vertices.row(b->vertex)).norm() <= tolerance) {
              clusters.unite(a->vertex, b->vertex);
            }
          }
        }
      }
      begin = end;
    }
  }
  std::vector<Eigen::Index> representative(vertices.rows());
  for (Eigen::Index v = 0; v < vertices.rows(); ++v) representative[v] = clusters.find(v);
  return representative;
}

/// Replaces every vertex by its representative and keeps only the vertices triangles use, in
/// index order (so colours follow their vertex).
void merge_into_representatives(TriangleMesh& mesh,
                                const std::vector<Eigen::Index>& representative) {
  std::vector<bool> used(mesh.num_vertices());
  for (const int v : mesh.triangles.reshaped()) used[representative[v]] = true;
  std::vector<int> new_index(mesh.num_vertices(), -1);
  std::vector<Eigen::Index> kept;
  for (Eigen::Index v = 0; v < mesh.num_vertices(); ++v) {
    if (!used[v]) continue;
    new_index[v] = static_cast<int>(kept.size());
    kept.push_back(v);
  }
  for (int& v : mesh.triangles.reshaped()) v = new_index[representative[v]];
  if (mesh.has_vertex_colors()) {
    mesh.vertex_colors = ColorMatrix(mesh.vertex_colors(kept, Eigen::all));
  }
  mesh.vertices = VertexMatrix(mesh.vertices(kept, Eigen::all));
}

/// Records, for each point orient_polygon_soup() appends, the input point it copies.
struct DuplicationRecorder : pmp::Default_orientation_visitor {
  std::vector<std::size_t>* origin = nullptr;  // CGAL copies visitors: the result lives outside
  void duplicated_vertex(std::size_t original, std::size_t copy) {
    if (origin->size() <= copy) origin->resize(copy + 1);
    (*origin)[copy] = original;
  }
};

using Surface = CGAL::Surface_mesh<Point>;

/// Reverses the connected components of `surface` that enclose a negative volume.
void turn_components_outward(Surface& surface) {
  const auto component = surface.add_property_map<Surface::Face_index, std::size_t>("f:cc").first;
  std::vector<double> six_volume(pmp::connected_components(surface, component));
  const Point& reference = surface.point(*surface.vertices().begin());
  for (const Surface::Face_index face : surface.faces()) {
    std::array<Kernel::Vector_3, 3> corner;
    int k = 0;
    for (const auto v : CGAL::vertices_around_face(surface.halfedge(face), surface)) {
      corner[k++] = surface.point(v) - reference;
    }
    six_volume[component[face]] +=
        CGAL::scalar_product(corner[0], CGAL::cross_product(corner[1], corner[2]));
  }
  std::vector<Surface::Face_index> inverted;
  for (const Surface::Face_index face : surface.faces()) {
    if (six_volume[component[face]] < 0.0) inverted.push_back(face);
  }
  pmp::reverse_face_orientations(inverted, surface);
}

/// For a soup that forms a closed surface, reverses the polygons needed for it to bound a
/// volume with outward normals.
void orient_outward_if_closed(const std::vector<Point>& points, std::vector<Polygon>& polygons) {
  if (polygons.empty() || !pmp::is_polygon_soup_a_polygon_mesh(polygons)) return;
  Surface surface;
  // Vertices and faces are created in soup order, so their indices are the soup's.
  pmp::polygon_soup_to_polygon_mesh(points, polygons, surface);
  if (!CGAL::is_closed(surface)) return;
  // CGAL's volume orientation also turns cavities inwards, but it requires a surface without
  // self-intersections or degenerate faces (it asserts, or reads out of bounds, otherwise).
  if (pmp::does_self_intersect(surface)) {
    turn_components_outward(surface);
  } else {
    pmp::orient_to_bound_a_volume(surface);
  }
  for (const Surface::Face_index face : surface.faces()) {
    Polygon& polygon = polygons[face.idx()];
    const auto kept = surface.halfedge(Surface::Vertex_index(Surface::size_type(polygon[0])),
                                       Surface::Vertex_index(Surface::size_type(polygon[1])));
    if (kept == Surface::null_halfedge() || surface.face(kept) != face) {
      std::swap(polygon[1], polygon[2]);
    }
  }
}

}  // namespace

Eigen::Index weld_vertices(TriangleMesh& mesh, double tolerance) {
  validate(mesh);
  if (!(tolerance >= 0.0 && std::isfinite(tolerance))) {
    throw MeshError("weld tolerance must be finite and non-negative, got " +
                    std::to_string(tolerance));
  }
  const Eigen::Index before = mesh.num_vertices();
  // Unused vertices go first, so that they cannot bridge two used ones.
  std::vector<Eigen::Index> identity(before);
  std::iota(identity.begin(), identity.end(), Eigen::Index{0});
  merge_into_representatives(mesh, identity);
  // Exact duplicates need no grid; the report counts them with the same code.
  merge_into_representatives(mesh, tolerance == 0.0
                                       ? detail::exact_duplicate_representatives(mesh.vertices)
                                       : nearby_representatives(mesh.vertices, tolerance));
  return before - mesh.num_vertices();
}

Eigen::Index remove_degenerate_triangles(TriangleMesh& mesh) {
  validate(mesh);
  std::vector<bool> remove =
      detail::degenerate_triangle_mask(mesh, detail::referenced_bounding_box(mesh));
  for (const Eigen::Index t : detail::duplicate_triangles(mesh)) remove[t] = true;
  std::vector<Eigen::Index> kept;
  for (Eigen::Index t = 0; t < mesh.num_triangles(); ++t) {
    if (!remove[t]) kept.push_back(t);
  }
  const Eigen::Index removed = mesh.num_triangles() - static_cast<Eigen::Index>(kept.size());
  mesh.triangles = TriangleMatrix(mesh.triangles(kept, Eigen::all));
  return removed;
}

bool orient_consistently(TriangleMesh& mesh) {
  validate(mesh);
  const Eigen::Index num_vertices = mesh.num_vertices();
  std::vector<Point> points;
  points.reserve(num_vertices);
  for (Eigen::Index v = 0; v < num_vertices; ++v) {
    points.emplace_back(mesh.vertices(v, 0), mesh.vertices(v, 1), mesh.vertices(v, 2));
  }
  // Triangles repeating a vertex have no orientation (and CGAL's soup functions refuse them).
  std::vector<Polygon> polygons;
  std::vector<Eigen::Index> polygon_triangle;
  for (Eigen::Index t = 0; t < mesh.num_triangles(); ++t) {
    if (detail::has_repeated_vertex(mesh, t)) continue;
    const auto tri = mesh.triangles.row(t);
    polygons.push_back({std::size_t(tri(0)), std::size_t(tri(1)), std::size_t(tri(2))});
    polygon_triangle.push_back(t);
  }

  std::vector<std::size_t> origin;
  DuplicationRecorder recorder;
  recorder.origin = &origin;
  pmp::orient_polygon_soup(points, polygons, CGAL::parameters::visitor(recorder));
  orient_outward_if_closed(points, polygons);

  const auto total = static_cast<Eigen::Index>(points.size());
  mesh.vertices.conservativeResize(total, Eigen::NoChange);
  if (mesh.has_vertex_colors()) mesh.vertex_colors.conservativeResize(total, Eigen::NoChange);
  for (Eigen::Index v = num_vertices; v < total; ++v) {
    const auto original = static_cast<Eigen::Index>(origin[v]);
    mesh.vertices.row(v) = mesh.vertices.row(original);
    if (mesh.has_vertex_colors()) mesh.vertex_colors.row(v) = mesh.vertex_colors.row(original);
  }
  for (std::size_t p = 0; p < polygons.size(); ++p) {
    for (int k = 0; k < 3; ++k) mesh.triangles(polygon_triangle[p], k) = int(polygons[p][k]);
  }
  return analyze_mesh(mesh).consistently_oriented;
}

RepairSummary repair_mesh(TriangleMesh& mesh, const RepairOptions& options) {
  validate(mesh);
  RepairSummary summary;
  // Written so that a NaN tolerance reaches weld_vertices() and is reported, not skipped.
  if (!(options.weld_tolerance < 0.0)) {
    summary.vertices_welded = weld_vertices(mesh, options.weld_tolerance);
  }
  if (options.remove_degenerate) summary.triangles_removed = remove_degenerate_triangles(mesh);
  if (options.orient) {
    const Eigen::Index before = mesh.num_vertices();
    summary.oriented = orient_consistently(mesh);
    summary.vertices_split = mesh.num_vertices() - before;
  }
  if (options.fill_holes) summary.holes = fill_holes(mesh);
  return summary;
}

}  // namespace khz::reduced
