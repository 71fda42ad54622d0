#pragma once
// Exact overlap test of a triangle and an axis-aligned box, the predicate of the voxelizer.

#include <algorithm>
#include <array>
#include <cmath>

namespace khz::reduced::detail {

/// True if the triangle and the closed axis-aligned box with the given centre and
/// half side length share at least one point (touching counts).
///
/// Separating-axis theorem: two convex sets are disjoint iff their projections onto one of a
/// finite set of axes are. For a triangle and a box the candidates are the three box face
/// normals, the triangle's normal and the nine cross products of a triangle edge with a box
/// axis. A degenerate triangle (a segment or a point) makes some candidates zero; a zero axis
/// projects everything to 0 and never separates, and the remaining axes are exactly the
/// candidates of the segment or point, so the test stays exact for it.
///
/// Written with scalar arrays rather than Eigen: it runs once per candidate voxel, and
/// unoptimized (Debug) Eigen code would make the voxelizer tests take seconds.
using Point3 = std::array<double, 3>;

inline bool triangle_overlaps_box(const std::array<Point3, 3>& triangle, const Point3& centre,
                                  double half_side) {
  using Vec = Point3;
  std::array<Vec, 3> v;
  for (int k = 0; k < 3; ++k) {
    for (int axis = 0; axis < 3; ++axis) v[k][axis] = triangle[k][axis] - centre[axis];
  }
  const auto dot = [](const Vec& p, const Vec& q) {
    return p[0] * q[0] + p[1] * q[1] + p[2] * q[2];
  };
  const auto cross = [](const Vec& p, const Vec& q) {
    return Vec{p[1] * q[2] - p[2] * q[1], p[2] * q[0] - p[0] * q[2], p[0] * q[1] - p[1] * q[0]};
  };
  const auto separates = [&](const Vec& axis) {
    const double p0 = dot(axis, v[0]);
    const double p1 = dot(axis, v[1]);
    const double p2 = dot(axis, v[2]);
    // The box's projection is centred at 0 with this half-width.
    const double radius = half_side * (std::abs(axis[0]) + std::abs(axis[1]) + std::abs(axis[2]));
    return std::min({p0, p1, p2}) > radius || std::max({p0, p1, p2}) < -radius;
  };
  const std::array<Vec, 3> edges = {Vec{v[1][0] - v[0][0], v[1][1] - v[0][1], v[1][2] - v[0][2]},
                                    Vec{v[2][0] - v[1][0], v[2][1] - v[1][1], v[2][2] - v[1][2]},
                                    Vec{v[0][0] - v[2][0], v[0][1] - v[2][1], v[0][2] - v[2][2]}};
  constexpr std::array<Vec, 3> box_axes = {Vec{1, 0, 0}, Vec{0, 1, 0}, Vec{0, 0, 1}};
  if (separates(cross(edges[0], edges[1]))) return false;  // the triangle's plane
  for (const Vec& axis : box_axes) {
    if (separates(axis)) return false;
  }
  for (const Vec& edge : edges) {
    for (const Vec& axis : box_axes) {
      if (separates(cross(edge, axis))) return false;
    }
  }
  return true;
}

}  // namespace khz::reduced::detail
