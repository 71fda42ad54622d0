#pragma once
// Near-uniform points on the unit sphere, for pointshell tests.

#include <khz/reduced/mesh/triangle_mesh.hpp>

#include <Eigen/Core>

#include <cmath>
#include <numbers>

namespace khz::test {

/// `count` points on the unit sphere by the golden spiral (Fibonacci lattice): uniform in z, so
/// every point stands for the same area, as a particle-repulsion pointshell's does (§3.8.1). Row
/// i is also the outward normal there.
inline reduced::VertexMatrix fibonacci_sphere_points(Eigen::Index count) {
  reduced::VertexMatrix points(count, 3);
  const double golden = std::numbers::pi * (3.0 - std::sqrt(5.0));
  for (Eigen::Index i = 0; i < count; ++i) {
    const double z = 1.0 - (2.0 * static_cast<double>(i) + 1.0) / static_cast<double>(count);
    const double ring = std::sqrt(1.0 - z * z);
    const double angle = golden * static_cast<double>(i);
    points.row(i) = Eigen::RowVector3d(ring * std::cos(angle), ring * std::sin(angle), z);
  }
  return points;
}

}  // namespace khz::test
