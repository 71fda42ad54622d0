#include <khz/contact/field/isosurface.hpp>
#include <khz/contact/field/polygon_soup_field.hpp>

#include "field/isosurface_detail.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <deque>
#include <limits>
#include <numeric>
#include <span>
#include <string>
#include <utility>
#include <vector>

namespace khz::contact {
namespace {

// Which level-set components are inner walls (thesis §3.8.1, §3.11: "remove any mesh components
// completely contained inside another component"), decided on the grid rather than by geometric
// inside tests, so that nearly touching components cannot fool it.
//
// The level set L = {U = σ} of the interpolated unsigned field U consists of disjoint closed
// surfaces (isosurface() makes the level regular by nudging). Let Ω be the part of the free
// region {U > σ} connected to the grid's boundary; its nodes are those reachable from the
// boundary nodes through nodes with U ≥ σ along tetrahedron edges (superlevel regions of a
// piecewise-linear function are connected exactly when their nodes are, within each simplex
// and hence along edges). A component is kept when its larger side is Ω, i.e. when the node at
// the upper end of any of its edges lies in Ω (all of its edges agree: adjacent triangles share
// a face's upper nodes).
//
// These are exactly the components inside no other: a component C bordering Ω lies outside
// every other component D, because Ω is connected, unbounded beyond the box and misses D, so it
// lies outside D, and C is in Ω's closure. Conversely the region outside all outermost
// components is connected, free of L and unbounded, so U > σ there: it is Ω, which therefore
// borders every outermost component. For the σ-shell around a closed or nearly closed soup the
// outer wall borders Ω and the inner wall borders the enclosed pocket, so the inner wall goes;
// the field keeps closed cavities "inside", as documented.

/// The nodes of the free region connected to the box's boundary (1) among all nodes (0 else).
/// All boundary nodes must lie above the level.
std::vector<std::uint8_t> outer_free_region(const DistanceGrid& grid, double level) {
  const GridGeometry& g = grid.geometry();
  const int n = g.nodes_per_axis();
  const std::span<const float> values = grid.values();
  std::int64_t offsets[14];
  for (int o = 0; o < 14; ++o) {
    const auto& d = detail::kTetrahedronNeighbours[o];
    offsets[o] = d[0] + std::int64_t{n} * (d[1] + std::int64_t{n} * d[2]);
  }
  std::vector<std::uint8_t> reached(static_cast<std::size_t>(g.node_count()), 0);
  // Breadth first from a corner (the boundary nodes are all above the level and connected), so
  // that the queue holds a front (~n² nodes), not a volume.
  std::deque<std::array<int, 3>> queue{{0, 0, 0}};
  reached[0] = 1;
  while (!queue.empty()) {
    const auto [i, j, k] = queue.front();
    queue.pop_front();
    const std::int64_t node = g.node_index(i, j, k);
    const bool interior = i > 0 && j > 0 && k > 0 && i + 1 < n && j + 1 < n && k + 1 < n;
    for (int o = 0; o < 14; ++o) {
      const auto& d = detail::kTetrahedronNeighbours[o];
      if (!interior && (std::min({i + d[0], j + d[1], k + d[2]}) < 0 ||
                        std::max({i + d[0], j + d[1], k + d[2]}) >= n)) {
        continue;
      }
      const auto next = static_cast<std::size_t>(node + offsets[o]);
      if (reached[next] != 0 || !(static_cast<double>(values[next]) >= level)) continue;
      reached[next] = 1;
      queue.push_back({i + d[0], j + d[1], k + d[2]});
    }
  }
  return reached;
}

/// The least node value on the box's six faces.
double smallest_boundary_value(const DistanceGrid& grid) {
  const int last = grid.geometry().cells;
  float smallest = std::numeric_limits<float>::infinity();
  for (int k = 0; k <= last; ++k) {
    for (int j = 0; j <= last; ++j) {
      const bool on_face = k == 0 || k == last || j == 0 || j == last;
      for (int i = 0; i <= last; i += on_face ? 1 : last) {
        smallest = std::min(smallest, grid.node(i, j, k));
      }
    }
  }
  return smallest;
}

/// Component label of every vertex (connected through shared triangles), labels 0…count − 1.
std::vector<int> vertex_components(const TriangleMesh& mesh, int& count) {
  std::vector<int> parent(static_cast<std::size_t>(mesh.num_vertices()));
  std::iota(parent.begin(), parent.end(), 0);
  const auto root = [&](int v) {
    while (parent[static_cast<std::size_t>(v)] != v) {
      int& up = parent[static_cast<std::size_t>(v)];
      up = parent[static_cast<std::size_t>(up)];  // path halving
      v = up;
    }
    return v;
  };
  for (Eigen::Index t = 0; t < mesh.num_triangles(); ++t) {
    const int a = root(mesh.triangles(t, 0));
    for (int c = 1; c < 3; ++c) {
      const int b = root(mesh.triangles(t, c));
      if (a != b) parent[static_cast<std::size_t>(b)] = a;
    }
  }
  std::vector<int> label(parent.size(), -1);
  count = 0;
  for (std::size_t v = 0; v < parent.size(); ++v) {
    const auto r = static_cast<std::size_t>(root(static_cast<int>(v)));
    if (label[r] < 0) label[r] = count++;
    label[v] = label[r];
  }
  return label;
}

/// The triangles of `mesh` whose vertices are kept, with the vertices renumbered in order.
TriangleMesh kept_part(const TriangleMesh& mesh, const std::vector<std::uint8_t>& keep_vertex) {
  std::vector<int> renumbered(keep_vertex.size(), -1);
  int vertices = 0;
  for (std::size_t v = 0; v < keep_vertex.size(); ++v) {
    if (keep_vertex[v] != 0) renumbered[v] = vertices++;
  }
  TriangleMesh part;
  part.vertices.resize(vertices, 3);
  for (std::size_t v = 0; v < keep_vertex.size(); ++v) {
    if (renumbered[v] >= 0) {
      part.vertices.row(renumbered[v]) = mesh.vertices.row(static_cast<Eigen::Index>(v));
    }
  }
  Eigen::Index triangles = 0;
  for (Eigen::Index t = 0; t < mesh.num_triangles(); ++t) {
    triangles += keep_vertex[static_cast<std::size_t>(mesh.triangles(t, 0))] != 0 ? 1 : 0;
  }
  part.triangles.resize(triangles, 3);
  Eigen::Index row = 0;
  for (Eigen::Index t = 0; t < mesh.num_triangles(); ++t) {
    if (keep_vertex[static_cast<std::size_t>(mesh.triangles(t, 0))] == 0) continue;
    for (int c = 0; c < 3; ++c) {
      part.triangles(row, c) = renumbered[static_cast<std::size_t>(mesh.triangles(t, c))];
    }
    ++row;
  }
  return part;
}

}  // namespace

PolygonSoupField polygon_soup_field(const TriangleMesh& soup,
                                    const PolygonSoupFieldOptions& options) {
  reduced::validate(soup);
  if (soup.num_triangles() == 0) throw MeshError("polygon_soup_field: the soup has no triangles");

  // One grid for both fields, fixed first so that σ can be checked before any work. Its box is
  // the one unsigned_distance_field() would choose itself.
  DistanceFieldOptions field_options = options.field;
  if (!field_options.geometry) {
    Eigen::AlignedBox3d bounds;
    bounds.setEmpty();
    for (Eigen::Index v = 0; v < soup.num_vertices(); ++v) {
      bounds.extend(soup.vertices.row(v).transpose());
    }
    field_options.geometry =
        GridGeometry::cube_around(bounds, field_options.box_expansion, field_options.cells);
  }
  const GridGeometry geometry = *field_options.geometry;
  geometry.validate();
  const double h = geometry.spacing;
  // σ > h keeps the level set off the soup's own cells, where the sampled field is least
  // smooth (thesis Fig. 3.15: 1.4 spacings).
  const double sigma = options.offset == 0.0 ? 1.4 * h : options.offset;
  if (!(std::isfinite(sigma) && sigma > h)) {
    throw Error("polygon_soup_field: the offset σ = " + std::to_string(sigma) +
                " must exceed the grid spacing h = " + std::to_string(h));
  }

  TriangleMesh offset_surface;
  int components_removed = 0;
  {  // the unsigned field and its flood fill are freed before the signed field is allocated
    const DistanceGrid unsigned_field = unsigned_distance_field(soup, field_options);
    // The level set closes inside the box only if every boundary node lies beyond σ (the
    // interpolant on the box's faces mixes boundary nodes only).
    const double boundary_nearest = smallest_boundary_value(unsigned_field);
    if (!(boundary_nearest > sigma)) {
      throw Error("polygon_soup_field: the offset surface at σ = " + std::to_string(sigma) +
                  " reaches the grid's boundary (a boundary node lies " +
                  std::to_string(boundary_nearest) +
                  " from the soup); raise box_expansion or lower the offset");
    }
    std::vector<std::int64_t> upper_nodes;
    const TriangleMesh level_set = detail::isosurface(unsigned_field, sigma, &upper_nodes);
    const std::vector<std::uint8_t> outside = outer_free_region(unsigned_field, sigma);
    int components = 0;
    const std::vector<int> component = vertex_components(level_set, components);
    // A component is outer when a vertex of it (any: they agree) has its upper node outside.
    std::vector<std::uint8_t> outer(static_cast<std::size_t>(components), 0);
    for (std::size_t v = 0; v < component.size(); ++v) {
      if (outside[static_cast<std::size_t>(upper_nodes[v])] != 0) {
        outer[static_cast<std::size_t>(component[v])] = 1;
      }
    }
    std::vector<std::uint8_t> keep_vertex(component.size());
    for (std::size_t v = 0; v < component.size(); ++v) {
      keep_vertex[v] = outer[static_cast<std::size_t>(component[v])];
    }
    offset_surface = kept_part(level_set, keep_vertex);
    components_removed =
        components - static_cast<int>(std::count(outer.begin(), outer.end(), std::uint8_t{1}));
  }
  if (offset_surface.num_triangles() == 0) {
    throw Error("polygon_soup_field: no level-set component remains at σ = " +
                std::to_string(sigma));
  }
  field_options.geometry = geometry;
  DistanceGrid field = signed_distance_field(offset_surface, field_options);
  return {std::move(field), std::move(offset_surface), components_removed, sigma};
}

}  // namespace khz::contact
