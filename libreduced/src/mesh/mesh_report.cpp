#include <khz/reduced/errors.hpp>
#include <khz/reduced/mesh/mesh_report.hpp>

#include "mesh/mesh_defects.hpp"
#include "mesh/union_find.hpp"

#include <algorithm>
#include <cstdint>
#include <ostream>
#include <vector>

namespace khz::reduced {
namespace {

/// Directed edge of a triangle, keyed by its undirected vertex pair so that sorting groups the
/// triangles around each edge.
struct HalfEdge {
  std::uint64_t edge;  // (lower vertex << 32) | higher vertex
  Eigen::Index id;     // 3·triangle + corner it starts from
  auto operator<=>(const HalfEdge&) const = default;
};

int start_vertex(const TriangleMesh& mesh, Eigen::Index half_edge) {
  return mesh.triangles(half_edge / 3, half_edge % 3);
}
int end_vertex(const TriangleMesh& mesh, Eigen::Index half_edge) {
  return mesh.triangles(half_edge / 3, (half_edge + 1) % 3);
}

/// Half-edges of the triangles with three distinct vertices, sorted by undirected edge.
std::vector<HalfEdge> sorted_half_edges(const TriangleMesh& mesh) {
  std::vector<HalfEdge> half_edges;
  half_edges.reserve(3 * mesh.num_triangles());
  for (Eigen::Index t = 0; t < mesh.num_triangles(); ++t) {
    if (detail::has_repeated_vertex(mesh, t)) continue;
    for (Eigen::Index h = 3 * t; h < 3 * t + 3; ++h) {
      const int a = start_vertex(mesh, h);
      const int b = end_vertex(mesh, h);
      const auto [lo, hi] = std::minmax(a, b);
      half_edges.push_back({(std::uint64_t(lo) << 32) | std::uint64_t(hi), h});
    }
  }
  std::sort(half_edges.begin(), half_edges.end());
  return half_edges;
}

/// The corner (3·triangle + k) of the half-edge's triangle that sits at `vertex`.
Eigen::Index corner_at(const TriangleMesh& mesh, Eigen::Index half_edge, int vertex) {
  return start_vertex(mesh, half_edge) == vertex ? half_edge
                                                 : half_edge - half_edge % 3 + (half_edge + 1) % 3;
}

/// Fills the edge, manifold, orientation, component and Euler fields. Purely combinatorial:
/// every triangle with three distinct vertices takes part, whatever its area.
void analyze_topology(const TriangleMesh& mesh, MeshReport& report) {
  const std::vector<HalfEdge> half_edges = sorted_half_edges(mesh);
  // Triangles joined across edges give components; corners joined across manifold edges give
  // the fans around each vertex (a corner is one triangle's wedge at one vertex).
  detail::UnionFind components(mesh.num_triangles());
  detail::UnionFind fans(3 * mesh.num_triangles());
  std::vector<bool> on_non_manifold_edge(mesh.num_vertices());
  bool opposite_directions = true;
  for (std::size_t begin = 0, end = 0; begin < half_edges.size(); begin = end) {
    while (end < half_edges.size() && half_edges[end].edge == half_edges[begin].edge) ++end;
    const Eigen::Index first = half_edges[begin].id;
    const auto incidences = end - begin;
    ++report.num_edges;
    for (std::size_t i = begin + 1; i < end; ++i) components.unite(first / 3, half_edges[i].id / 3);
    if (incidences == 1) {
      ++report.num_boundary_edges;
    } else if (incidences == 2) {
      const Eigen::Index second = half_edges[begin + 1].id;
      opposite_directions &= start_vertex(mesh, first) != start_vertex(mesh, second);
      for (const int v : {start_vertex(mesh, first), end_vertex(mesh, first)}) {
        fans.unite(corner_at(mesh, first, v), corner_at(mesh, second, v));
      }
    } else {
      ++report.num_non_manifold_edges;
      on_non_manifold_edge[start_vertex(mesh, first)] = true;
      on_non_manifold_edge[end_vertex(mesh, first)] = true;
    }
  }

  std::vector<int> fans_per_vertex(mesh.num_vertices());
  Eigen::Index used_faces = 0;
  for (Eigen::Index t = 0; t < mesh.num_triangles(); ++t) {
    if (detail::has_repeated_vertex(mesh, t)) continue;
    ++used_faces;
    if (components.find(t) == t) ++report.num_components;
    for (Eigen::Index c = 3 * t; c < 3 * t + 3; ++c) {
      if (fans.find(c) == c) ++fans_per_vertex[start_vertex(mesh, c)];
    }
  }
  Eigen::Index used_vertices = 0;
  for (Eigen::Index v = 0; v < mesh.num_vertices(); ++v) {
    if (fans_per_vertex[v] > 0) ++used_vertices;
    if (fans_per_vertex[v] > 1 && !on_non_manifold_edge[v]) ++report.num_non_manifold_vertices;
  }

  report.edge_manifold = report.num_non_manifold_edges == 0;
  report.vertex_manifold = report.edge_manifold && report.num_non_manifold_vertices == 0;
  report.consistently_oriented = report.edge_manifold && opposite_directions;
  report.closed = used_faces > 0 && report.vertex_manifold && report.num_boundary_edges == 0;
  report.euler_characteristic = used_vertices - report.num_edges + used_faces;
}

/// Surface area and signed volume. The volume is taken about the box centre: the same value
/// for a closed surface, with far less cancellation when the mesh sits away from the origin.
void measure(const TriangleMesh& mesh, MeshReport& report) {
  const Eigen::Vector3d origin =
      report.bounding_box.isEmpty() ? Eigen::Vector3d(0, 0, 0) : report.bounding_box.center();
  double twice_area = 0.0;
  double six_volume = 0.0;  // scaled once at the end: one rounding instead of one per triangle
  for (Eigen::Index t = 0; t < mesh.num_triangles(); ++t) {
    const Eigen::Vector3d a = mesh.vertices.row(mesh.triangles(t, 0)).transpose() - origin;
    const Eigen::Vector3d b = mesh.vertices.row(mesh.triangles(t, 1)).transpose() - origin;
    const Eigen::Vector3d c = mesh.vertices.row(mesh.triangles(t, 2)).transpose() - origin;
    twice_area += (b - a).cross(c - a).norm();
    six_volume += a.dot(b.cross(c));
  }
  report.surface_area = 0.5 * twice_area;
  report.signed_volume = six_volume / 6.0;
}

const char* yes_no(bool value) { return value ? "yes" : "no"; }

}  // namespace

MeshReport analyze_mesh(const TriangleMesh& mesh) {
  validate(mesh);
  MeshReport report;
  report.num_vertices = mesh.num_vertices();
  report.num_triangles = mesh.num_triangles();
  report.bounding_box = detail::referenced_bounding_box(mesh);

  const std::vector<bool> degenerate = detail::degenerate_triangle_mask(mesh, report.bounding_box);
  for (Eigen::Index t = 0; t < mesh.num_triangles(); ++t) {
    if (degenerate[t]) report.degenerate_triangles.push_back(t);
  }
  report.duplicate_triangles = detail::duplicate_triangles(mesh);

  std::vector<bool> referenced(mesh.num_vertices());
  for (const int v : mesh.triangles.reshaped()) referenced[v] = true;
  report.num_unreferenced_vertices = std::count(referenced.begin(), referenced.end(), false);
  const std::vector<Eigen::Index> representative =
      detail::exact_duplicate_representatives(mesh.vertices);
  for (Eigen::Index v = 0; v < mesh.num_vertices(); ++v) {
    if (representative[v] != v) ++report.num_duplicate_vertices;
  }

  analyze_topology(mesh, report);
  measure(mesh, report);
  return report;
}

std::ostream& operator<<(std::ostream& out, const MeshReport& report) {
  out << "vertices:      " << report.num_vertices << " (" << report.num_unreferenced_vertices
      << " unreferenced, " << report.num_duplicate_vertices << " duplicate positions)\n";
  out << "triangles:     " << report.num_triangles << " (" << report.degenerate_triangles.size()
      << " degenerate, " << report.duplicate_triangles.size() << " duplicate)\n";
  out << "edges:         " << report.num_edges << " (" << report.num_boundary_edges << " boundary, "
      << report.num_non_manifold_edges << " non-manifold)\n";
  if (report.bounding_box.isEmpty()) {
    out << "bounding box:  empty\n";
  } else {
    const Eigen::IOFormat row(Eigen::StreamPrecision, Eigen::DontAlignCols, ", ", ", ", "", "", "(",
                              ")");
    out << "bounding box:  min " << report.bounding_box.min().transpose().format(row) << ", max "
        << report.bounding_box.max().transpose().format(row) << ", size "
        << report.bounding_box.sizes().transpose().format(row) << '\n';
  }
  out << "components:    " << report.num_components << '\n';
  out << "manifold:      " << yes_no(report.vertex_manifold);
  if (!report.vertex_manifold) {
    out << " (" << report.num_non_manifold_edges << " non-manifold edges, "
        << report.num_non_manifold_vertices << " non-manifold vertices)";
  }
  out << "\nclosed:        " << yes_no(report.closed);
  if (!report.closed) {
    if (report.num_edges == 0) {
      out << " (no edges)";
    } else if (report.num_boundary_edges > 0) {
      out << " (" << report.num_boundary_edges << " boundary edges)";
    } else {
      out << " (not manifold)";
    }
  }
  out << "\noriented:      " << yes_no(report.consistently_oriented);
  if (!report.consistently_oriented) {
    out << (report.edge_manifold ? " (neighbouring triangles disagree)" : " (non-manifold edges)");
  }
  out << "\neuler char.:   " << report.euler_characteristic << '\n';
  out << "surface area:  " << report.surface_area << '\n';
  out << "volume:        ";
  if (report.closed && report.consistently_oriented) {
    out << report.signed_volume << '\n';
  } else {
    out << "n/a (not a closed, oriented surface)\n";
  }
  return out;
}

}  // namespace khz::reduced
