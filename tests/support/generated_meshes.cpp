#include <khz/test/generated_meshes.hpp>

#include <cmath>
#include <numbers>
#include <random>

namespace khz::test {

using reduced::TriangleMesh;

TriangleMesh unit_cube_surface() {
  TriangleMesh mesh;
  mesh.vertices.resize(8, 3);
  for (int v = 0; v < 8; ++v) mesh.vertices.row(v) << (v & 1), ((v >> 1) & 1), ((v >> 2) & 1);
  mesh.triangles.resize(12, 3);
  // Vertex v has x = bit 0, y = bit 1, z = bit 2; each face split along a diagonal, outward.
  mesh.triangles << 0, 2, 1, 1, 2, 3,  // z = 0
      4, 5, 6, 5, 7, 6,                // z = 1
      0, 1, 4, 1, 5, 4,                // y = 0
      2, 6, 3, 3, 6, 7,                // y = 1
      0, 4, 2, 2, 4, 6,                // x = 0
      1, 3, 5, 3, 7, 5;                // x = 1
  return mesh;
}

TriangleMesh unit_square() {
  TriangleMesh mesh;
  mesh.vertices.resize(4, 3);
  mesh.vertices << 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0;
  mesh.triangles.resize(2, 3);
  mesh.triangles << 0, 1, 2, 0, 2, 3;
  return mesh;
}

TriangleMesh uv_sphere(int slices, int stacks) {
  TriangleMesh mesh;
  const int rings = stacks - 1;
  mesh.vertices.resize(2 + rings * slices, 3);
  mesh.vertices.row(0) << 0, 0, 1;
  mesh.vertices.row(1) << 0, 0, -1;
  for (int i = 0; i < rings; ++i) {
    const double theta = std::numbers::pi * (i + 1) / stacks;
    for (int j = 0; j < slices; ++j) {
      const double phi = 2.0 * std::numbers::pi * j / slices;
      mesh.vertices.row(2 + i * slices + j) << std::sin(theta) * std::cos(phi),
          std::sin(theta) * std::sin(phi), std::cos(theta);
    }
  }
  const auto ring_vertex = [&](int i, int j) { return 2 + i * slices + (j % slices); };
  mesh.triangles.resize(2 * slices * rings, 3);
  int t = 0;
  for (int j = 0; j < slices; ++j) {
    mesh.triangles.row(t++) << 0, ring_vertex(0, j), ring_vertex(0, j + 1);
    mesh.triangles.row(t++) << 1, ring_vertex(rings - 1, j + 1), ring_vertex(rings - 1, j);
  }
  for (int i = 0; i + 1 < rings; ++i) {
    for (int j = 0; j < slices; ++j) {
      mesh.triangles.row(t++) << ring_vertex(i, j), ring_vertex(i + 1, j),
          ring_vertex(i + 1, j + 1);
      mesh.triangles.row(t++) << ring_vertex(i, j), ring_vertex(i + 1, j + 1),
          ring_vertex(i, j + 1);
    }
  }
  return mesh;
}

TriangleMesh random_soup(int count, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> coordinate(-1.0, 1.0);
  std::uniform_int_distribution<int> channel(0, 255);
  TriangleMesh mesh;
  mesh.vertices.resize(3 * count, 3);
  mesh.vertex_colors.resize(3 * count, 4);
  mesh.triangles.resize(count, 3);
  for (int v = 0; v < 3 * count; ++v) {
    for (int c = 0; c < 3; ++c) mesh.vertices(v, c) = coordinate(rng);
    for (int c = 0; c < 4; ++c)
      mesh.vertex_colors(v, c) = static_cast<float>(channel(rng)) / 255.0f;
  }
  for (int t = 0; t < count; ++t) mesh.triangles.row(t) << 3 * t, 3 * t + 1, 3 * t + 2;
  return mesh;
}

}  // namespace khz::test
