// Hole filling: every loop of boundary edges closed by triangles over its own vertices.

#include <khz/reduced/errors.hpp>
#include <khz/reduced/mesh/mesh_repair.hpp>
#include <khz/reduced/mesh/mesh_report.hpp>

#include "mesh/mesh_defects.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/triangulate_hole.h>
#include <CGAL/utility.h>

#include <algorithm>
#include <iterator>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace khz::reduced {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;

/// Directed edge (a, b) → how many triangles traverse it, over the triangles with three
/// distinct vertices.
using DirectedEdges = std::map<std::pair<int, int>, int>;

DirectedEdges directed_edges(const TriangleMesh& mesh) {
  DirectedEdges directed;
  for (Eigen::Index t = 0; t < mesh.num_triangles(); ++t) {
    if (detail::has_repeated_vertex(mesh, t)) continue;
    for (int k = 0; k < 3; ++k) ++directed[{mesh.triangles(t, k), mesh.triangles(t, (k + 1) % 3)}];
  }
  return directed;
}

/// The loops of boundary edges, each in the direction its triangle traverses it: an edge (a, b)
/// of a triangle is on the boundary when no triangle traverses (b, a). In an edge-manifold,
/// consistently oriented mesh each boundary vertex starts one boundary edge, unless holes touch.
/// @throws MeshError where two holes share a vertex (the loops would be ambiguous).
std::vector<std::vector<int>> boundary_loops(const DirectedEdges& directed) {
  std::map<int, int> next;  // boundary edge a → b, keyed by a
  for (const auto& [edge, count] : directed) {
    if (directed.contains({edge.second, edge.first})) continue;
    if (!next.emplace(edge.first, edge.second).second) {
      throw MeshError("fill_holes: two holes meet at vertex " + std::to_string(edge.first) +
                      "; weld or repair the mesh first");
    }
  }
  std::vector<std::vector<int>> loops;
  while (!next.empty()) {
    std::vector<int> loop{next.begin()->first};
    for (int v = next.begin()->second; v != loop.front();) {
      loop.push_back(v);
      const auto step = next.find(v);
      if (step == next.end()) {
        throw MeshError("fill_holes: the boundary through vertex " + std::to_string(v) +
                        " does not close into a loop");
      }
      v = step->second;
    }
    for (const int v : loop) next.erase(v);
    loops.push_back(std::move(loop));
  }
  return loops;
}

/// Undirected edge key.
std::pair<int, int> undirected(int a, int b) { return a < b ? std::pair(a, b) : std::pair(b, a); }

}  // namespace

HoleFilling fill_holes(TriangleMesh& mesh) {
  validate(mesh);
  const MeshReport report = analyze_mesh(mesh);
  if (!report.edge_manifold) {
    throw MeshError(
        "fill_holes needs an edge-manifold, consistently oriented surface, but it has " +
        std::to_string(report.num_non_manifold_edges) + " non-manifold edges");
  }
  if (!report.consistently_oriented) {
    throw MeshError(
        "fill_holes needs an edge-manifold, consistently oriented surface, but it is not "
        "consistently oriented (orient_consistently() first)");
  }
  const DirectedEdges directed = directed_edges(mesh);
  const std::vector<std::vector<int>> loops = boundary_loops(directed);
  std::map<std::pair<int, int>, int> edges;  // undirected edge → triangles using it
  for (const auto& [edge, count] : directed) edges[undirected(edge.first, edge.second)] += count;
  HoleFilling result;
  std::vector<Eigen::RowVector3i> added;
  for (const std::vector<int>& loop : loops) {
    std::vector<Point> polyline;
    for (const int v : loop)
      polyline.emplace_back(mesh.vertices(v, 0), mesh.vertices(v, 1), mesh.vertices(v, 2));
    std::vector<CGAL::Triple<int, int, int>> patch;
    CGAL::Polygon_mesh_processing::triangulate_hole_polyline(polyline, std::back_inserter(patch));
    if (patch.empty()) {
      ++result.left_open;
      continue;
    }
    // The surface traverses loop[i] → loop[i+1]; the patch must traverse it the other way. Find
    // how the patch's triangle on the edge loop[0]–loop[1] runs, and flip the patch if needed.
    bool same_direction = false;
    for (const auto& t : patch) {
      const int corners[3] = {t.first, t.second, t.third};
      for (int k = 0; k < 3; ++k) {
        if (corners[k] == 0 && corners[(k + 1) % 3] == 1) same_direction = true;
      }
    }
    // A patch whose triangles would give an edge a third triangle (a chord of the loop that is
    // already an edge, as where holes nearly touch) would make the surface non-manifold.
    std::map<std::pair<int, int>, int> patch_edges;  // undirected edge → patch triangles using it
    for (const auto& t : patch) {
      const int corners[3] = {loop[t.first], loop[t.second], loop[t.third]};
      for (int k = 0; k < 3; ++k) ++patch_edges[undirected(corners[k], corners[(k + 1) % 3])];
    }
    const bool manifold =
        std::all_of(patch_edges.begin(), patch_edges.end(), [&](const auto& entry) {
          const auto existing = edges.find(entry.first);
          return (existing == edges.end() ? 0 : existing->second) + entry.second <= 2;
        });
    if (!manifold) {
      ++result.left_open;
      continue;
    }
    for (const auto& [edge, count] : patch_edges) edges[edge] += count;
    for (const auto& t : patch) {
      const int a = loop[t.first], b = loop[t.second], c = loop[t.third];
      added.push_back(same_direction ? Eigen::RowVector3i(a, c, b) : Eigen::RowVector3i(a, b, c));
    }
    ++result.filled;
  }
  const Eigen::Index old_count = mesh.num_triangles();
  mesh.triangles.conservativeResize(old_count + static_cast<Eigen::Index>(added.size()),
                                    Eigen::NoChange);
  for (std::size_t i = 0; i < added.size(); ++i) {
    mesh.triangles.row(old_count + static_cast<Eigen::Index>(i)) = added[i];
  }
  return result;
}

}  // namespace khz::reduced
