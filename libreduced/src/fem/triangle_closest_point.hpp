#pragma once
// Closest point of a triangle to a point: the distance from a point outside a volume mesh to the
// boundary of an element (MeshEmbedding's nearest-element search).

#include <Eigen/Core>

namespace khz::reduced::detail {

struct TriangleClosestPoint {
  Eigen::Vector3d barycentric;  ///< Of the closest point, w.r.t. corners (a, b, c); all ≥ 0.
  double squared_distance = 0.0;
};

/// The point of triangle (a, b, c) nearest to x. Degenerate triangles (collinear or coincident
/// corners) are handled as their edges.
TriangleClosestPoint closest_point_on_triangle(const Eigen::Vector3d& x, const Eigen::Vector3d& a,
                                               const Eigen::Vector3d& b,
                                               const Eigen::Vector3d& c) noexcept;

}  // namespace khz::reduced::detail
