#pragma once
// Areas of triangle meshes.

#include <khz/reduced/mesh/triangle_mesh.hpp>

#include <Eigen/Core>

namespace khz::reduced {

/// Area of triangle t (square metres); indices are not checked.
inline double triangle_area(const TriangleMesh& mesh, Eigen::Index t) noexcept {
  const Eigen::Vector3d a = mesh.vertices.row(mesh.triangles(t, 0)).transpose();
  const Eigen::Vector3d b = mesh.vertices.row(mesh.triangles(t, 1)).transpose();
  const Eigen::Vector3d c = mesh.vertices.row(mesh.triangles(t, 2)).transpose();
  return 0.5 * (b - a).cross(c - a).norm();
}

/// Sum of the triangle areas (square metres), in triangle order.
inline double surface_area(const TriangleMesh& mesh) noexcept {
  double area = 0.0;
  for (Eigen::Index t = 0; t < mesh.num_triangles(); ++t) area += triangle_area(mesh, t);
  return area;
}

}  // namespace khz::reduced
