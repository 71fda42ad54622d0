#include "fem/element_coloring.hpp"

#include <algorithm>
#include <cstdint>
#include <utility>

namespace khz::reduced::detail {
namespace {

/// Spreads the low 10 bits of x to every third bit (bit i → bit 3i).
std::uint32_t spread_bits(std::uint32_t x) {
  x &= 0x3ffu;
  x = (x | (x << 16)) & 0x030000ffu;
  x = (x | (x << 8)) & 0x0300f00fu;
  x = (x | (x << 4)) & 0x030c30c3u;
  x = (x | (x << 2)) & 0x09249249u;
  return x;
}

/// Elements in Morton order of their centroids on a 1024³ grid over the mesh's bounding box, so
/// consecutive elements are close in space.
std::vector<int> morton_order(const VolumeMesh& mesh) {
  const int count = static_cast<int>(mesh.num_elements());
  const int nodes = static_cast<int>(mesh.elements.cols());
  const Eigen::RowVector3d low = mesh.vertices.colwise().minCoeff();
  const Eigen::RowVector3d extent = mesh.vertices.colwise().maxCoeff() - low;
  const double cell = std::max(extent.maxCoeff(), 1e-300) / 1023.0;
  std::vector<std::pair<std::uint32_t, int>> keyed(count);
  for (int e = 0; e < count; ++e) {
    Eigen::RowVector3d centroid = Eigen::RowVector3d::Zero();
    for (int a = 0; a < nodes; ++a) centroid += mesh.vertices.row(mesh.elements(e, a));
    const Eigen::RowVector3d grid = (centroid / nodes - low) / cell;
    std::uint32_t code = 0;
    for (int axis = 0; axis < 3; ++axis) {
      code |= spread_bits(static_cast<std::uint32_t>(std::clamp(grid[axis], 0.0, 1023.0))) << axis;
    }
    keyed[e] = {code, e};
  }
  std::sort(keyed.begin(), keyed.end());
  std::vector<int> order(count);
  for (int i = 0; i < count; ++i) order[i] = keyed[i].second;
  return order;
}

}  // namespace

ElementColoring color_elements(const VolumeMesh& mesh, int chunk_size) {
  const int num_elements = static_cast<int>(mesh.num_elements());
  const int num_vertices = static_cast<int>(mesh.num_vertices());
  const int nodes = static_cast<int>(mesh.elements.cols());
  ElementColoring coloring;
  if (num_elements == 0) {
    coloring.chunk_offsets.push_back(0);
    coloring.color_offsets.push_back(0);
    return coloring;
  }
  const std::vector<int> sorted = morton_order(mesh);
  const int num_chunks = (num_elements + chunk_size - 1) / chunk_size;
  auto chunk_elements = [&](int chunk) {
    return std::pair(sorted.begin() + chunk * chunk_size,
                     sorted.begin() + std::min(num_elements, (chunk + 1) * chunk_size));
  };

  // Chunks around each vertex (CSR, possibly with repeats), to find a chunk's neighbours.
  std::vector<int> start(num_vertices + 1, 0);
  for (int e = 0; e < num_elements; ++e) {
    for (int a = 0; a < nodes; ++a) ++start[mesh.elements(e, a) + 1];
  }
  for (int v = 0; v < num_vertices; ++v) start[v + 1] += start[v];
  std::vector<int> incident(start.back());
  std::vector<int> fill(start.begin(), start.end() - 1);
  for (int chunk = 0; chunk < num_chunks; ++chunk) {
    const auto [first, last] = chunk_elements(chunk);
    for (auto e = first; e != last; ++e) {
      for (int a = 0; a < nodes; ++a) incident[fill[mesh.elements(*e, a)]++] = chunk;
    }
  }

  std::vector<int> color(num_chunks, -1);
  // forbidden[c] == chunk marks colour c as taken by a neighbour of `chunk`: no clearing needed.
  std::vector<int> forbidden;
  for (int chunk = 0; chunk < num_chunks; ++chunk) {
    const auto [first, last] = chunk_elements(chunk);
    for (auto e = first; e != last; ++e) {
      for (int a = 0; a < nodes; ++a) {
        const int v = mesh.elements(*e, a);
        for (int i = start[v]; i < start[v + 1]; ++i) {
          const int c = color[incident[i]];
          if (c >= 0) forbidden[c] = chunk;
        }
      }
    }
    const int colors = static_cast<int>(forbidden.size());
    int c = 0;
    while (c < colors && forbidden[c] == chunk) ++c;
    if (c == colors) forbidden.push_back(-1);
    color[chunk] = c;
  }

  // Chunks grouped by colour, stable so each colour sweeps along the curve.
  const int num_colors = static_cast<int>(forbidden.size());
  coloring.color_offsets.assign(num_colors + 1, 0);
  for (int chunk = 0; chunk < num_chunks; ++chunk) ++coloring.color_offsets[color[chunk] + 1];
  for (int c = 0; c < num_colors; ++c) coloring.color_offsets[c + 1] += coloring.color_offsets[c];
  std::vector<int> chunks(num_chunks);
  std::vector<int> next(coloring.color_offsets.begin(), coloring.color_offsets.end() - 1);
  for (int chunk = 0; chunk < num_chunks; ++chunk) chunks[next[color[chunk]]++] = chunk;

  coloring.order.reserve(num_elements);
  coloring.chunk_offsets.reserve(num_chunks + 1);
  for (const int chunk : chunks) {
    coloring.chunk_offsets.push_back(static_cast<int>(coloring.order.size()));
    const auto [first, last] = chunk_elements(chunk);
    coloring.order.insert(coloring.order.end(), first, last);
  }
  coloring.chunk_offsets.push_back(num_elements);
  return coloring;
}

}  // namespace khz::reduced::detail
