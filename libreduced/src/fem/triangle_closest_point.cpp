#include "fem/triangle_closest_point.hpp"

#include <algorithm>
#include <array>

namespace khz::reduced::detail {

TriangleClosestPoint closest_point_on_triangle(const Eigen::Vector3d& x, const Eigen::Vector3d& a,
                                               const Eigen::Vector3d& b,
                                               const Eigen::Vector3d& c) noexcept {
  // If x projects into the triangle, the projection is nearest; otherwise the nearest point lies
  // on an edge (the triangle is convex), so the best of the three edge projections wins.
  const Eigen::Vector3d ab = b - a;
  const Eigen::Vector3d ac = c - a;
  const Eigen::Vector3d ax = x - a;
  const double ab_ab = ab.dot(ab);
  const double ab_ac = ab.dot(ac);
  const double ac_ac = ac.dot(ac);
  const double gram = ab_ab * ac_ac - ab_ac * ab_ac;  // |ab × ac|², 0 for degenerate triangles
  if (gram > 0.0) {
    // Projection = a + v·ab + w·ac, from the 2×2 normal equations (Cramer's rule).
    const double ab_ax = ab.dot(ax);
    const double ac_ax = ac.dot(ax);
    const double v = (ac_ac * ab_ax - ab_ac * ac_ax) / gram;
    const double w = (ab_ab * ac_ax - ab_ac * ab_ax) / gram;
    if (v >= 0.0 && w >= 0.0 && v + w <= 1.0) {
      return {{1.0 - v - w, v, w}, (ax - v * ab - w * ac).squaredNorm()};
    }
  }
  const std::array<const Eigen::Vector3d*, 3> corners{&a, &b, &c};
  TriangleClosestPoint best;
  best.squared_distance = -1.0;
  for (int edge = 0; edge < 3; ++edge) {
    const int from = edge;
    const int to = (edge + 1) % 3;
    const Eigen::Vector3d direction = *corners[to] - *corners[from];
    const double length2 = direction.squaredNorm();
    const double t =
        length2 > 0.0 ? std::clamp((x - *corners[from]).dot(direction) / length2, 0.0, 1.0) : 0.0;
    const double d2 = (x - *corners[from] - t * direction).squaredNorm();
    if (best.squared_distance < 0.0 || d2 < best.squared_distance) {
      best.barycentric.setZero();
      best.barycentric[from] = 1.0 - t;
      best.barycentric[to] = t;
      best.squared_distance = d2;
    }
  }
  return best;
}

}  // namespace khz::reduced::detail
