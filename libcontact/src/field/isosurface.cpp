#include <khz/contact/field/isosurface.hpp>
#include <khz/reduced/worker_threads.hpp>

#include "field/isosurface_detail.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <climits>
#include <cmath>
#include <cstdint>
#include <exception>
#include <string>
#include <utility>
#include <vector>

namespace khz::contact {
namespace {

// Marching tetrahedra over Kuhn's split of every cell (thesis §3.8.1 and §3.11 use marching cubes;
// tetrahedra need no case table to copy and have no ambiguous case). The level set of the
// piecewise-linear interpolant over the tetrahedra is a closed 2-manifold wherever the level is
// not a node value, and each triangle of it lies in one tetrahedron.
//
// Cell corners are numbered by their offsets from the cell's lowest node: bit 0 is +x, bit 1 +y,
// bit 2 +z. Every edge of the split joins two corners a, b of which one's offsets are a subset of
// the other's, so it starts at corner a & b and runs along the offsets a ^ b (1…7): seven edge
// directions per node, the same in every cell. That is what makes the split consistent across
// cell faces, and it names each mesh vertex by (node, direction) so neighbours share it.

/// Vertices stay this fraction of an edge away from its nodes: a node exactly at the level is
/// nudged to the larger side (and a node within rounding of it stays clear), so that the
/// vertices of the edges meeting at a node never coincide and no triangle is degenerate.
constexpr double kNodeClearance = 1e-6;

/// The six tetrahedra, one per monotone path from corner 0 to corner 7: corners 0, e_a,
/// e_a + e_b, 7 for each permutation (a, b, c) of the axes. Such a tetrahedron's orientation is
/// det(e_a, e_b, e_c), the permutation's sign; the odd ones list their middle corners swapped so
/// that all six are positively oriented, which the orientation rule of kCases relies on.
constexpr std::array<std::array<int, 4>, 6> kTetrahedra = [] {
  constexpr int permutations[6][3] = {{0, 1, 2}, {1, 2, 0}, {2, 0, 1},   // even
                                      {0, 2, 1}, {2, 1, 0}, {1, 0, 2}};  // odd
  std::array<std::array<int, 4>, 6> tetrahedra{};
  for (int t = 0; t < 6; ++t) {
    const int first = 1 << permutations[t][0];
    const int second = first | (1 << permutations[t][1]);
    tetrahedra[t] = t < 3 ? std::array{0, first, second, 7} : std::array{0, second, first, 7};
  }
  return tetrahedra;
}();

/// How a positively oriented tetrahedron is cut, given which of its vertices lie on the larger
/// side (bit v of the case index set for vertex v).
struct Cut {
  int below = 0;  ///< Number of vertices below the level.
  /// The vertices, those below first, as an even permutation of 0, 1, 2, 3: the ordered
  /// tetrahedron stays positively oriented, so one rule orients every case (see emit_cut()).
  std::array<int, 4> order{};
};

constexpr std::array<Cut, 16> kCuts = [] {
  std::array<Cut, 16> cuts{};
  for (int above = 0; above < 16; ++above) {
    Cut& cut = cuts[above];
    int filled = 0;
    for (int v = 0; v < 4; ++v) {
      if (((above >> v) & 1) == 0) cut.order[filled++] = v;
    }
    cut.below = filled;
    for (int v = 0; v < 4; ++v) {
      if (((above >> v) & 1) != 0) cut.order[filled++] = v;
    }
    int inversions = 0;
    for (int a = 0; a < 4; ++a) {
      for (int b = a + 1; b < 4; ++b) inversions += cut.order[a] > cut.order[b] ? 1 : 0;
    }
    // An odd order becomes even by swapping two vertices on the same side.
    if (inversions % 2 == 1) {
      if (cut.below == 3) {
        std::swap(cut.order[1], cut.order[2]);
      } else {
        std::swap(cut.order[2], cut.order[3]);
      }
    }
  }
  return cuts;
}();

/// The node values and where the nodes are.
struct Lattice {
  const float* values;
  int n;  // nodes per axis
  std::int64_t n2;
  double level;
  Eigen::Vector3d origin;
  double spacing;

  std::int64_t index(int i, int j, int k) const noexcept {
    return k * n2 + std::int64_t{j} * n + i;
  }
  bool above(std::int64_t node) const noexcept {
    return static_cast<double>(values[node]) >= level;
  }

  /// The vertex on the edge from node (i, j, k) along the offsets `direction` (1…7), where the
  /// linear interpolant along the edge meets the level; in `upper` the edge's node on the larger
  /// side. Deterministic, so a recomputation gives the stored position bit for bit.
  Eigen::Vector3d crossing(int i, int j, int k, int direction, std::int64_t& upper) const noexcept {
    const int di = direction & 1, dj = (direction >> 1) & 1, dk = (direction >> 2) & 1;
    const std::int64_t a = index(i, j, k), b = index(i + di, j + dj, k + dk);
    const double va = values[a], vb = values[b];
    // One end is below the level and the other not, so vb ≠ va.
    const double t = std::clamp((level - va) / (vb - va), kNodeClearance, 1.0 - kNodeClearance);
    upper = va >= level ? a : b;
    return origin + spacing * Eigen::Vector3d(i + t * di, j + t * dj, k + t * dk);
  }
};

/// One layer of nodes: which side each node is on, which of its seven edges cross the level
/// (bit direction − 1) and the index of the first of their vertices (the others follow in
/// direction order).
struct Slice {
  std::vector<std::uint8_t> above;
  std::vector<std::uint8_t> crossing;
  std::vector<int> first_vertex;

  int vertex(std::int64_t node, int direction) const noexcept {
    const unsigned lower =
        crossing[static_cast<std::size_t>(node)] & ((1u << (direction - 1)) - 1u);
    return first_vertex[static_cast<std::size_t>(node)] + std::popcount(lower);
  }
};

/// Counts the crossing edges starting in node layer k; fills `slice` if given, numbering the
/// vertices from `first`, and writes their positions (and upper nodes) if `vertices` is given.
std::int64_t scan_slice(const Lattice& g, int k, Slice* slice, std::int64_t first,
                        TriangleMesh* vertices, std::int64_t* upper_nodes) {
  const int n = g.n;
  if (slice != nullptr) {
    const auto size = static_cast<std::size_t>(g.n2);
    slice->above.resize(size);
    slice->crossing.resize(size);
    slice->first_vertex.resize(size);
  }
  std::int64_t count = 0;
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      const std::int64_t node = g.index(i, j, k);
      const bool up = g.above(node);
      unsigned crossing = 0;
      for (int d = 1; d < 8; ++d) {
        const int di = d & 1, dj = (d >> 1) & 1, dk = (d >> 2) & 1;
        if (i + di < n && j + dj < n && k + dk < n &&
            g.above(node + di + dj * std::int64_t{n} + dk * g.n2) != up) {
          crossing |= 1u << (d - 1);
        }
      }
      if (slice != nullptr) {
        const auto in_slice = static_cast<std::size_t>(std::int64_t{j} * n + i);
        slice->above[in_slice] = up ? 1 : 0;
        slice->crossing[in_slice] = static_cast<std::uint8_t>(crossing);
        slice->first_vertex[in_slice] = static_cast<int>(first + count);
      }
      if (vertices != nullptr) {
        for (int d = 1; d < 8; ++d) {
          if ((crossing & (1u << (d - 1))) == 0) continue;
          const std::int64_t row = first + count + std::popcount(crossing & ((1u << (d - 1)) - 1u));
          std::int64_t upper = 0;
          vertices->vertices.row(row) = g.crossing(i, j, k, d, upper).transpose();
          if (upper_nodes != nullptr) upper_nodes[row] = upper;
        }
      }
      count += std::popcount(crossing);
    }
  }
  return count;
}

/// The triangles of cell layer k (between node layers k and k + 1), appended to `triangles` as
/// index triples.
void march_layer(const Lattice& g, int k, const Slice& lower, const Slice& upper,
                 std::vector<int>& triangles) {
  const int n = g.n;
  const Slice* slices[2] = {&lower, &upper};
  for (int j = 0; j + 1 < n; ++j) {
    for (int i = 0; i + 1 < n; ++i) {
      const auto corner_node = [&](int corner) {
        return std::int64_t{j + ((corner >> 1) & 1)} * n + i + (corner & 1);
      };
      unsigned corners_above = 0;
      for (int c = 0; c < 8; ++c) {
        corners_above |= unsigned{slices[c >> 2]->above[static_cast<std::size_t>(corner_node(c))]}
                         << c;
      }
      if (corners_above == 0 || corners_above == 0xff) continue;

      // The vertex on the edge between cell corners a and b, and its position.
      const auto vertex = [&](int a, int b) {
        const int base = a & b;
        return slices[base >> 2]->vertex(corner_node(base), a ^ b);
      };
      const auto position = [&](int a, int b) {
        const int base = a & b;
        std::int64_t unused = 0;
        return g.crossing(i + (base & 1), j + ((base >> 1) & 1), k + (base >> 2), a ^ b, unused);
      };

      for (const std::array<int, 4>& tetrahedron : kTetrahedra) {
        unsigned above = 0;
        for (int v = 0; v < 4; ++v) above |= ((corners_above >> tetrahedron[v]) & 1u) << v;
        const Cut& cut = kCuts[above];
        if (cut.below == 0 || cut.below == 4) continue;
        // The ordered tetrahedron (o0, o1, o2, o3) is positively oriented, its vertices below
        // the level first. Its face (o1, o2, o3) is counter-clockwise seen from outside, i.e.
        // facing away from o0, and so is the triangle cutting the edges from o0 towards those
        // vertices; that is the larger side when o0 is the one vertex below. Likewise face
        // (o0, o1, o2) faces o3, and the cut near o3 faces it: the larger side when o3 is the
        // one vertex above. With two on each side the cut quadrilateral (o0o2, o0o3, o1o3, o1o2)
        // faces o2 and o3 (check: o = (0, x, y, z), level halfway).
        const auto o = [&](int v) { return tetrahedron[cut.order[v]]; };
        if (cut.below == 1) {
          triangles.insert(triangles.end(),
                           {vertex(o(0), o(1)), vertex(o(0), o(2)), vertex(o(0), o(3))});
        } else if (cut.below == 3) {
          triangles.insert(triangles.end(),
                           {vertex(o(0), o(3)), vertex(o(1), o(3)), vertex(o(2), o(3))});
        } else {
          const int q[4] = {vertex(o(0), o(2)), vertex(o(0), o(3)), vertex(o(1), o(3)),
                            vertex(o(1), o(2))};
          // Split along the shorter diagonal, for better-shaped triangles.
          const double d02 = (position(o(0), o(2)) - position(o(1), o(3))).squaredNorm();
          const double d13 = (position(o(0), o(3)) - position(o(1), o(2))).squaredNorm();
          if (d02 <= d13) {
            triangles.insert(triangles.end(), {q[0], q[1], q[2], q[0], q[2], q[3]});
          } else {
            triangles.insert(triangles.end(), {q[0], q[1], q[3], q[1], q[2], q[3]});
          }
        }
      }
    }
  }
}

/// Node layers per work item: a fixed split, so the output does not depend on the thread count.
constexpr int kLayersPerBlock = 4;

}  // namespace

namespace detail {

TriangleMesh isosurface(const DistanceGrid& grid, double level,
                        std::vector<std::int64_t>* upper_nodes) {
  if (!std::isfinite(level)) throw Error("isosurface: the level is not finite");
  const GridGeometry& geometry = grid.geometry();
  const int n = geometry.nodes_per_axis();
  const Lattice lattice{grid.values().data(), n, std::int64_t{n} * n, level, geometry.origin,
                        geometry.spacing};

  // Pass 1: vertices per node layer, so that both vertex and triangle numbering are fixed before
  // the parallel pass and independent of the schedule.
  std::vector<std::int64_t> layer_vertices(static_cast<std::size_t>(n) + 1, 0);
#pragma omp parallel for num_threads(reduced::worker_threads()) schedule(static)
  for (int k = 0; k < n; ++k) {
    layer_vertices[static_cast<std::size_t>(k) + 1] =
        scan_slice(lattice, k, nullptr, 0, nullptr, nullptr);
  }
  for (int k = 0; k < n; ++k) {
    layer_vertices[static_cast<std::size_t>(k) + 1] += layer_vertices[static_cast<std::size_t>(k)];
  }
  const std::int64_t vertex_count = layer_vertices.back();
  if (vertex_count > INT_MAX) {
    throw Error("isosurface: " + std::to_string(vertex_count) +
                " vertices exceed the 32-bit triangle indices");
  }

  TriangleMesh mesh;
  mesh.vertices.resize(vertex_count, 3);
  if (upper_nodes != nullptr) upper_nodes->assign(static_cast<std::size_t>(vertex_count), 0);
  if (vertex_count == 0) {
    mesh.triangles.resize(0, 3);
    return mesh;
  }

  // Pass 2: per block of node layers, their vertices and the triangles of the cell layers
  // starting in them. A block also scans the first layer of the next block (for its last cell
  // layer) but leaves that layer's vertices to their owner.
  const int blocks = (n + kLayersPerBlock - 1) / kLayersPerBlock;
  std::vector<std::vector<int>> block_triangles(static_cast<std::size_t>(blocks));
  std::exception_ptr failure;
#pragma omp parallel for num_threads(reduced::worker_threads()) schedule(dynamic)
  for (int block = 0; block < blocks; ++block) {
    try {
      const int begin = block * kLayersPerBlock;
      const int end = std::min(begin + kLayersPerBlock, n);
      std::int64_t* uppers = upper_nodes != nullptr ? upper_nodes->data() : nullptr;
      Slice lower, upper;
      scan_slice(lattice, begin, &lower, layer_vertices[static_cast<std::size_t>(begin)], &mesh,
                 uppers);
      std::vector<int>& triangles = block_triangles[static_cast<std::size_t>(block)];
      for (int k = begin; k < end && k + 1 < n; ++k) {
        const bool owned = k + 1 < end;
        scan_slice(lattice, k + 1, &upper, layer_vertices[static_cast<std::size_t>(k) + 1],
                   owned ? &mesh : nullptr, owned ? uppers : nullptr);
        march_layer(lattice, k, lower, upper, triangles);
        std::swap(lower, upper);
      }
    } catch (...) {
#pragma omp critical(khz_isosurface_failure)
      if (!failure) failure = std::current_exception();
    }
  }
  if (failure) std::rethrow_exception(failure);

  std::int64_t index_count = 0;
  for (const std::vector<int>& triangles : block_triangles) {
    index_count += static_cast<std::int64_t>(triangles.size());
  }
  mesh.triangles.resize(index_count / 3, 3);
  int* out = mesh.triangles.data();
  for (std::vector<int>& triangles : block_triangles) {
    out = std::copy(triangles.begin(), triangles.end(), out);
    std::vector<int>().swap(triangles);
  }
  return mesh;
}

}  // namespace detail

TriangleMesh isosurface(const DistanceGrid& grid, double level) {
  return detail::isosurface(grid, level, nullptr);
}

}  // namespace khz::contact
