#pragma once
// Reference answers for the mesh-distance tests, computed independently of the library: brute
// force over all triangles by plane projection, the winding number by solid angles, and the
// small closed meshes the tests build.

#include <khz/reduced/mesh/triangle_mesh.hpp>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>
#include <utility>

namespace khz::test {

/// Distance from p to segment [a, b].
inline double segment_distance(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                               const Eigen::Vector3d& b) {
  const Eigen::Vector3d ab = b - a;
  const double length2 = ab.squaredNorm();
  const double t = length2 > 0.0 ? std::clamp((p - a).dot(ab) / length2, 0.0, 1.0) : 0.0;
  return (p - (a + t * ab)).norm();
}

/// Distance from p to triangle (a, b, c): the projection onto its plane if it falls inside (all
/// three edge tests agree with the normal), else the nearest edge.
inline double triangle_distance(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  const Eigen::Vector3d n = (b - a).cross(c - a);
  const double n2 = n.squaredNorm();
  if (n2 > 0.0) {
    const Eigen::Vector3d q = p - ((p - a).dot(n) / n2) * n;
    if ((b - a).cross(q - a).dot(n) >= 0.0 && (c - b).cross(q - b).dot(n) >= 0.0 &&
        (a - c).cross(q - c).dot(n) >= 0.0) {
      return (p - q).norm();
    }
  }
  return std::min(
      {segment_distance(p, a, b), segment_distance(p, b, c), segment_distance(p, c, a)});
}

inline Eigen::Vector3d corner(const reduced::TriangleMesh& mesh, Eigen::Index t, int k) {
  return mesh.vertices.row(mesh.triangles(t, k)).transpose();
}

inline double triangle_distance(const reduced::TriangleMesh& mesh, Eigen::Index t,
                                const Eigen::Vector3d& p) {
  return triangle_distance(p, corner(mesh, t, 0), corner(mesh, t, 1), corner(mesh, t, 2));
}

/// Unsigned distance from p to the mesh by visiting every triangle.
inline double brute_force_distance(const reduced::TriangleMesh& mesh, const Eigen::Vector3d& p) {
  double best = std::numeric_limits<double>::infinity();
  for (Eigen::Index t = 0; t < mesh.num_triangles(); ++t) {
    best = std::min(best, triangle_distance(mesh, t, p));
  }
  return best;
}

/// Generalized winding number of a closed, outward-oriented mesh around p: the sum of the
/// triangles' signed solid angles over 4π (van Oosterom & Strackee); 1 inside, 0 outside.
inline double winding_number(const reduced::TriangleMesh& mesh, const Eigen::Vector3d& p) {
  double sum = 0.0;
  for (Eigen::Index t = 0; t < mesh.num_triangles(); ++t) {
    const Eigen::Vector3d a = corner(mesh, t, 0) - p;
    const Eigen::Vector3d b = corner(mesh, t, 1) - p;
    const Eigen::Vector3d c = corner(mesh, t, 2) - p;
    const double la = a.norm(), lb = b.norm(), lc = c.norm();
    const double numerator = a.dot(b.cross(c));
    const double denominator = la * lb * lc + a.dot(b) * lc + a.dot(c) * lb + b.dot(c) * la;
    sum += 2.0 * std::atan2(numerator, denominator);
  }
  return sum / (4.0 * std::numbers::pi);
}

/// Closed, outward-oriented icosphere of radius 1: the icosahedron with each triangle split
/// into four `subdivisions` times, new vertices pushed onto the sphere.
inline reduced::TriangleMesh icosphere(int subdivisions) {
  const double g = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<Eigen::Vector3d> vertices = {{-1, g, 0}, {1, g, 0}, {-1, -g, 0}, {1, -g, 0},
                                           {0, -1, g}, {0, 1, g}, {0, -1, -g}, {0, 1, -g},
                                           {g, 0, -1}, {g, 0, 1}, {-g, 0, -1}, {-g, 0, 1}};
  for (auto& v : vertices) v.normalize();
  std::vector<Eigen::Vector3i> faces = {
      {0, 11, 5},  {0, 5, 1},  {0, 1, 7},  {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
      {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
      {3, 8, 9},   {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  for (int level = 0; level < subdivisions; ++level) {
    std::map<std::pair<int, int>, int> midpoints;
    const auto midpoint = [&](int a, int b) {
      const auto key = std::minmax(a, b);
      const auto found = midpoints.find(key);
      if (found != midpoints.end()) return found->second;
      vertices.push_back(
          (vertices[static_cast<std::size_t>(a)] + vertices[static_cast<std::size_t>(b)])
              .normalized());
      const int index = static_cast<int>(vertices.size()) - 1;
      midpoints.emplace(key, index);
      return index;
    };
    std::vector<Eigen::Vector3i> finer;
    for (const auto& f : faces) {
      const int ab = midpoint(f[0], f[1]), bc = midpoint(f[1], f[2]), ca = midpoint(f[2], f[0]);
      finer.insert(finer.end(), {{f[0], ab, ca}, {f[1], bc, ab}, {f[2], ca, bc}, {ab, bc, ca}});
    }
    faces = std::move(finer);
  }
  reduced::TriangleMesh mesh;
  mesh.vertices.resize(static_cast<Eigen::Index>(vertices.size()), 3);
  for (std::size_t v = 0; v < vertices.size(); ++v) {
    mesh.vertices.row(static_cast<Eigen::Index>(v)) = vertices[v].transpose();
  }
  mesh.triangles.resize(static_cast<Eigen::Index>(faces.size()), 3);
  for (std::size_t f = 0; f < faces.size(); ++f) {
    mesh.triangles.row(static_cast<Eigen::Index>(f)) = faces[f].transpose();
  }
  return mesh;
}

/// Closed, outward-oriented torus around the z axis: tube radius r at distance R, `around`
/// segments along the ring and `tube` around the tube. Its inner ring has saddle vertices.
inline reduced::TriangleMesh torus(double R, double r, int around, int tube) {
  reduced::TriangleMesh mesh;
  mesh.vertices.resize(around * tube, 3);
  const auto index = [&](int u, int v) { return (u % around) * tube + (v % tube); };
  for (int u = 0; u < around; ++u) {
    const double phi = 2.0 * std::numbers::pi * u / around;
    for (int v = 0; v < tube; ++v) {
      const double theta = 2.0 * std::numbers::pi * v / tube;
      const double radius = R + r * std::cos(theta);
      mesh.vertices.row(index(u, v)) << radius * std::cos(phi), radius * std::sin(phi),
          r * std::sin(theta);
    }
  }
  mesh.triangles.resize(2 * around * tube, 3);
  int t = 0;
  for (int u = 0; u < around; ++u) {
    for (int v = 0; v < tube; ++v) {
      mesh.triangles.row(t++) << index(u, v), index(u + 1, v), index(u + 1, v + 1);
      mesh.triangles.row(t++) << index(u, v), index(u + 1, v + 1), index(u, v + 1);
    }
  }
  return mesh;
}

}  // namespace khz::test
