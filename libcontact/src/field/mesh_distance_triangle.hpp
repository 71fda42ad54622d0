#pragma once
// The closest point of one triangle to a query point, and the feature (face, edge or vertex) it
// lies on: the Voronoi-region test of the triangle's vertices, edges and face, written with
// dot products only so that it needs no square root and no plane projection.

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <algorithm>
#include <cstdint>

namespace khz::contact::detail {

/// Where on triangle (a, b, c) a closest point lies. Edge k joins corner k and corner (k+1) % 3
/// (edge 0 = ab, 1 = bc, 2 = ca); vertex k is corner k.
enum class TriangleRegion : std::uint8_t { face, edge0, edge1, edge2, vertex0, vertex1, vertex2 };

inline TriangleRegion edge_region(int edge) noexcept {
  return static_cast<TriangleRegion>(static_cast<int>(TriangleRegion::edge0) + edge);
}
inline TriangleRegion vertex_region(int corner) noexcept {
  return static_cast<TriangleRegion>(static_cast<int>(TriangleRegion::vertex0) + corner);
}

/// Whether triangle (a, b, c) is too thin to have a face normal or reliable face regions: twice
/// its area is at most 1e-12 of its longest edge squared (the sine of its largest angle is below
/// about 1e-12), which includes collinear corners and repeated vertices.
inline bool is_degenerate_triangle(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                   const Eigen::Vector3d& c) noexcept {
  const double longest2 =
      std::max({(b - a).squaredNorm(), (c - b).squaredNorm(), (a - c).squaredNorm()});
  const double area2 = (b - a).cross(c - a).norm();
  return !(area2 > 1e-12 * longest2);
}

/// A closest point and the region holding it.
struct TrianglePoint {
  Eigen::Vector3d point;
  TriangleRegion region;
};

/// The closest point of segment [a, b] (edge `edge` of its triangle) to p; an endpoint is
/// reported as the corresponding vertex. A zero-length segment gives its first endpoint.
inline TrianglePoint closest_on_segment(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                        const Eigen::Vector3d& b, int edge) noexcept {
  const Eigen::Vector3d ab = b - a;
  const double length2 = ab.squaredNorm();
  const double t = length2 > 0.0 ? (p - a).dot(ab) / length2 : 0.0;
  if (!(t > 0.0)) return {a, vertex_region(edge)};
  if (t >= 1.0) return {b, vertex_region((edge + 1) % 3)};
  return {a + t * ab, edge_region(edge)};
}

/// The closest point of a degenerate (collinear or collapsed) triangle: the best of its three
/// edges. It never reports the face, which has no normal.
inline TrianglePoint closest_on_degenerate_triangle(const Eigen::Vector3d& p,
                                                    const Eigen::Vector3d& a,
                                                    const Eigen::Vector3d& b,
                                                    const Eigen::Vector3d& c) noexcept {
  TrianglePoint best = closest_on_segment(p, a, b, 0);
  double best2 = (p - best.point).squaredNorm();
  const TrianglePoint bc = closest_on_segment(p, b, c, 1);
  const double bc2 = (p - bc.point).squaredNorm();
  if (bc2 < best2) {
    best = bc;
    best2 = bc2;
  }
  const TrianglePoint ca = closest_on_segment(p, c, a, 2);
  if ((p - ca.point).squaredNorm() < best2) best = ca;
  return best;
}

/// The closest point of a non-degenerate triangle (a, b, c) to p. Each region test compares
/// dot products of p's offsets from the corners with the edge vectors: p lies in a vertex's
/// region when it is behind both edges leaving that vertex, in an edge's region when it is
/// between that edge's end planes and outside the edge (a signed area of the barycentric
/// coordinates is negative), and over the face otherwise. Callers route degenerate triangles to
/// closest_on_degenerate_triangle(); the divisions are still guarded so that nothing here is
/// ever NaN for finite input.
inline TrianglePoint closest_on_triangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                         const Eigen::Vector3d& b,
                                         const Eigen::Vector3d& c) noexcept {
  const Eigen::Vector3d ab = b - a;
  const Eigen::Vector3d ac = c - a;
  const Eigen::Vector3d ap = p - a;
  const double d1 = ab.dot(ap);
  const double d2 = ac.dot(ap);
  if (d1 <= 0.0 && d2 <= 0.0) return {a, TriangleRegion::vertex0};

  const Eigen::Vector3d bp = p - b;
  const double d3 = ab.dot(bp);
  const double d4 = ac.dot(bp);
  if (d3 >= 0.0 && d4 <= d3) return {b, TriangleRegion::vertex1};

  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
    const double denominator = d1 - d3;
    const double t = denominator > 0.0 ? d1 / denominator : 0.0;
    return {a + t * ab, TriangleRegion::edge0};
  }

  const Eigen::Vector3d cp = p - c;
  const double d5 = ab.dot(cp);
  const double d6 = ac.dot(cp);
  if (d6 >= 0.0 && d5 <= d6) return {c, TriangleRegion::vertex2};

  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
    const double denominator = d2 - d6;
    const double t = denominator > 0.0 ? d2 / denominator : 0.0;
    return {a + t * ac, TriangleRegion::edge2};
  }

  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0) {
    const double denominator = (d4 - d3) + (d5 - d6);
    const double t = denominator > 0.0 ? (d4 - d3) / denominator : 0.0;
    return {b + t * (c - b), TriangleRegion::edge1};
  }

  const double sum = va + vb + vc;
  if (!(sum > 0.0)) return closest_on_degenerate_triangle(p, a, b, c);
  const double v = vb / sum;
  const double w = vc / sum;
  return {a + v * ab + w * ac, TriangleRegion::face};
}

/// A triangle prepared for many squared-distance evaluations, in one 64-byte cache line: its
/// first corner (double), its edge vectors b − a and c − a and their dot products (float), so
/// that a query costs three dot products and the region test of closest_on_triangle() on
/// scalars. The float edges move the corners by about 1e-7 of the edge lengths, and the
/// squared distance comes from |p − a|² less the squared length of p − a's part along the
/// triangle, which loses about 1e-16·|p − a|²: fine for ranking candidate triangles far from
/// the surface, not for final values.
struct alignas(64) PreparedTriangle {
  double a[3];
  float ab[3], ac[3];
  float ab_ab, ab_ac, ac_ac;
  bool degenerate;

  PreparedTriangle(const Eigen::Vector3d& a_, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                   bool degenerate_) noexcept
      : a{a_.x(), a_.y(), a_.z()}, degenerate(degenerate_) {
    for (int axis = 0; axis < 3; ++axis) {
      ab[axis] = static_cast<float>(b[axis] - a_[axis]);
      ac[axis] = static_cast<float>(c[axis] - a_[axis]);
    }
    const Eigen::Vector3d u = edge_ab(), w = edge_ac();
    ab_ab = static_cast<float>(u.squaredNorm());
    ab_ac = static_cast<float>(u.dot(w));
    ac_ac = static_cast<float>(w.squaredNorm());
  }
  Eigen::Vector3d corner_a() const noexcept { return {a[0], a[1], a[2]}; }
  Eigen::Vector3d edge_ab() const noexcept { return {ab[0], ab[1], ab[2]}; }
  Eigen::Vector3d edge_ac() const noexcept { return {ac[0], ac[1], ac[2]}; }

  double squared_distance(const Eigen::Vector3d& p) const noexcept {
    const Eigen::Vector3d ap = p - corner_a();
    const Eigen::Vector3d u = edge_ab(), w = edge_ac();
    const auto through_edges = [&] {
      const TrianglePoint closest =
          closest_on_degenerate_triangle(ap, Eigen::Vector3d::Zero(), u, w);
      return (ap - closest.point).squaredNorm();
    };
    if (degenerate) return through_edges();
    const double pp = ap.squaredNorm();
    const double uu = ab_ab, uw = ab_ac, ww = ac_ac;
    const double d1 = u.dot(ap);
    const double d2 = w.dot(ap);
    if (d1 <= 0.0 && d2 <= 0.0) return pp;  // vertex a
    const double d3 = d1 - uu;
    const double d4 = d2 - uw;
    if (d3 >= 0.0 && d4 <= d3) return std::max(pp - 2.0 * d1 + uu, 0.0);  // vertex b
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) return std::max(pp - d1 * d1 / uu, 0.0);  // ab
    const double d5 = d1 - uw;
    const double d6 = d2 - ww;
    if (d6 >= 0.0 && d5 <= d6) return std::max(pp - 2.0 * d2 + ww, 0.0);  // vertex c
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) return std::max(pp - d2 * d2 / ww, 0.0);  // ca
    const double va = d3 * d6 - d5 * d4;
    const double along_bc = d4 - d3;
    if (va <= 0.0 && along_bc >= 0.0 && d5 - d6 >= 0.0) {  // bc
      const double bc_bc = along_bc + (d5 - d6);
      return std::max(pp - 2.0 * d1 + uu - along_bc * along_bc / bc_bc, 0.0);
    }
    const double sum = va + vb + vc;
    // A triangle whose float edges became (nearly) collinear has no face region.
    if (!(sum > 0.0)) return through_edges();
    return std::max(pp - (vb * d1 + vc * d2) / sum, 0.0);  // face
  }
};
static_assert(sizeof(PreparedTriangle) == 64);

}  // namespace khz::contact::detail
