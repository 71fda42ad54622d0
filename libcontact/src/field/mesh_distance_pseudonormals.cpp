#include "field/mesh_distance_pseudonormals.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>

namespace khz::contact::detail {
namespace {

Eigen::Vector3d normalized_or_zero(const Eigen::Vector3d& v) {
  const double norm = v.norm();
  return norm > 0.0 ? Eigen::Vector3d(v / norm) : Eigen::Vector3d::Zero();
}

}  // namespace

std::vector<TrianglePseudonormals> compute_pseudonormals(const PointMatrix& vertices,
                                                         const TriangleMatrix& triangles) {
  const auto count = static_cast<std::size_t>(triangles.rows());
  std::vector<TrianglePseudonormals> normals(count);
  std::vector<Eigen::Vector3d> vertex_sums(static_cast<std::size_t>(vertices.rows()),
                                           Eigen::Vector3d::Zero());
  const auto corner = [&](std::size_t t, int k) -> Eigen::Vector3d {
    return vertices.row(triangles(static_cast<Eigen::Index>(t), k)).transpose();
  };
  for (std::size_t t = 0; t < count; ++t) {
    const Eigen::Vector3d a = corner(t, 0), b = corner(t, 1), c = corner(t, 2);
    if (is_degenerate_triangle(a, b, c)) {
      normals[t].face.setZero();
      continue;
    }
    const Eigen::Vector3d n = (b - a).cross(c - a).normalized();
    normals[t].face = n;
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d from = corner(t, k);
      const Eigen::Vector3d u = corner(t, (k + 1) % 3) - from;
      const Eigen::Vector3d w = corner(t, (k + 2) % 3) - from;
      const double angle = std::atan2(u.cross(w).norm(), u.dot(w));
      vertex_sums[static_cast<std::size_t>(triangles(static_cast<Eigen::Index>(t), k))] +=
          angle * n;
    }
  }
  for (std::size_t t = 0; t < count; ++t) {
    for (int k = 0; k < 3; ++k) {
      normals[t].vertex[k] = normalized_or_zero(
          vertex_sums[static_cast<std::size_t>(triangles(static_cast<Eigen::Index>(t), k))]);
    }
  }

  // Edges: every (triangle, edge) keyed by its sorted vertex pair; equal keys are one edge,
  // whose pseudonormal is the sum of its faces' normals (each face's angle there is π).
  struct EdgeUse {
    std::uint64_t key;
    std::uint32_t triangle;
    int edge;
  };
  std::vector<EdgeUse> uses;
  uses.reserve(3 * count);
  for (std::size_t t = 0; t < count; ++t) {
    for (int k = 0; k < 3; ++k) {
      auto v0 = static_cast<std::uint32_t>(triangles(static_cast<Eigen::Index>(t), k));
      auto v1 = static_cast<std::uint32_t>(triangles(static_cast<Eigen::Index>(t), (k + 1) % 3));
      if (v1 < v0) std::swap(v0, v1);
      uses.push_back({(std::uint64_t{v0} << 32) | v1, static_cast<std::uint32_t>(t), k});
    }
  }
  std::sort(uses.begin(), uses.end(),
            [](const EdgeUse& x, const EdgeUse& y) { return x.key < y.key; });
  for (std::size_t begin = 0; begin < uses.size();) {
    std::size_t end = begin;
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (; end < uses.size() && uses[end].key == uses[begin].key; ++end) {
      sum += normals[uses[end].triangle].face;
    }
    const Eigen::Vector3d n = normalized_or_zero(sum);
    for (std::size_t u = begin; u < end; ++u) normals[uses[u].triangle].edge[uses[u].edge] = n;
    begin = end;
  }
  return normals;
}

}  // namespace khz::contact::detail
