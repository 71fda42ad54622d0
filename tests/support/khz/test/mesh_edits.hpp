#pragma once
// Edits that turn the generated meshes into defective ones, shared by the mesh report and
// mesh repair tests.

#include <khz/reduced/mesh/triangle_mesh.hpp>
#include <khz/test/generated_meshes.hpp>

#include <Eigen/Core>

namespace khz::test {

/// `mesh` with the vertex (x, y, z) appended (vertex colours are not kept).
inline reduced::TriangleMesh with_vertex(reduced::TriangleMesh mesh, double x, double y, double z) {
  mesh.vertices.conservativeResize(mesh.num_vertices() + 1, Eigen::NoChange);
  mesh.vertices.bottomRows<1>() << x, y, z;
  mesh.vertex_colors.resize(0, 4);
  return mesh;
}

/// `mesh` with the triangle (a, b, c) appended.
inline reduced::TriangleMesh with_triangle(reduced::TriangleMesh mesh, int a, int b, int c) {
  mesh.triangles.conservativeResize(mesh.num_triangles() + 1, Eigen::NoChange);
  mesh.triangles.bottomRows<1>() << a, b, c;
  return mesh;
}

/// `mesh` with triangle `t` traversed the other way round.
inline reduced::TriangleMesh with_flipped(reduced::TriangleMesh mesh, Eigen::Index t) {
  mesh.triangles.row(t).reverseInPlace();
  return mesh;
}

/// `first` and `second` in one mesh, `second` moved by `offset` and numbered after `first`
/// (vertex colours are not kept).
inline reduced::TriangleMesh combined(const reduced::TriangleMesh& first,
                                      const reduced::TriangleMesh& second,
                                      const Eigen::RowVector3d& offset) {
  reduced::TriangleMesh mesh;
  mesh.vertices.resize(first.num_vertices() + second.num_vertices(), 3);
  mesh.vertices << first.vertices, second.vertices.rowwise() + offset;
  mesh.triangles.resize(first.num_triangles() + second.num_triangles(), 3);
  mesh.triangles << first.triangles,
      second.triangles.array() + static_cast<int>(first.num_vertices());
  return mesh;
}

/// Two unit cubes touching at one corner (a "bow tie"): the second cube, moved by (1, 1, 1),
/// uses the first cube's vertex 7 as its own corner 0. 15 vertices, 24 triangles.
inline reduced::TriangleMesh cubes_sharing_a_corner() {
  reduced::TriangleMesh mesh =
      combined(unit_cube_surface(), unit_cube_surface(), Eigen::RowVector3d(1, 1, 1));
  // Vertex 8 (the second cube's corner 0) coincides with vertex 7: use 7, and move the last
  // vertex into the freed slot.
  for (int& v : mesh.triangles.reshaped()) {
    if (v == 8) v = 7;
    if (v == 15) v = 8;
  }
  mesh.vertices.row(8) = mesh.vertices.row(15);
  mesh.vertices.conservativeResize(15, Eigen::NoChange);
  return mesh;
}

}  // namespace khz::test
