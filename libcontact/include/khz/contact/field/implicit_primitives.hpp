#pragma once
// Analytic signed distance functions of simple solids, used in place of a sampled distance field
// when the obstacle is that simple (thesis §3.11.1): exact, smooth away from the medial axis, no
// memory, no resolution limit. Each satisfies DistanceField; ImplicitShape (implicit_shapes.hpp)
// places and combines them.
//
// Conventions of every primitive: metres, negative inside; distance() and
// distance_and_gradient() are noexcept, allocation-free and thread-safe. The gradient is that of
// the returned function, a unit vector wherever that function is the exact distance and
// differentiable; on the medial axis (several nearest boundary points: the centre of a sphere,
// the diagonal planes inside a box) it is a fixed choice among the one-sided gradients, as each
// type documents.
// Constructors validate their parameters and throw Error naming the bad one.

#include <khz/contact/common.hpp>
#include <khz/contact/export.hpp>

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <vector>

namespace khz::contact {

/// The half-space {p : n·p ≤ c} with unit outward normal n: n·p − c, the exact signed distance
/// to its plane everywhere.
class KHZ_CONTACT_API HalfSpace {
 public:
  /// @param normal outward normal, any non-zero length (normalized here).
  /// @param offset c (m): the plane is {p : n·p = c} for the normalized n.
  /// @throws Error if `normal` is zero or not finite, or `offset` is not finite.
  HalfSpace(const Eigen::Vector3d& normal, double offset);
  /// The half-space whose boundary plane passes through `point` (m), with outward `normal`.
  /// @throws Error as the constructor.
  static HalfSpace through(const Eigen::Vector3d& point, const Eigen::Vector3d& normal);

  const Eigen::Vector3d& normal() const noexcept { return m_normal; }  ///< Unit, outward.
  double offset() const noexcept { return m_offset; }                  ///< c (m).

  double distance(const Eigen::Vector3d& p) const noexcept { return m_normal.dot(p) - m_offset; }
  double distance_and_gradient(const Eigen::Vector3d& p, Eigen::Vector3d& gradient) const noexcept {
    gradient = m_normal;
    return distance(p);
  }

 private:
  Eigen::Vector3d m_normal;
  double m_offset;
};

/// The intersection of half-spaces {p : n_i·p ≤ c_i}: a slab, a wedge, a convex polytope. Its
/// function is max_i (n_i·p − c_i). That is the exact signed distance inside (for a convex set
/// the nearest face plane is the nearest boundary) and outside wherever the nearest boundary
/// point is inside a face; beyond an edge or a corner it is smaller than the distance, a lower
/// bound, as DistanceField allows. Exact everywhere for one plane or a slab. The gradient is the
/// normal of the maximizing plane (the first of equal ones). An empty intersection is not
/// detected: its function is positive everywhere.
class KHZ_CONTACT_API ConvexPolytope {
 public:
  /// @throws Error if `half_spaces` is empty.
  explicit ConvexPolytope(std::vector<HalfSpace> half_spaces);
  /// The slab {p : lower ≤ n·p ≤ upper} between two parallel planes, n = normal normalized.
  /// @throws Error if `normal` is zero or not finite, a bound is not finite, or lower ≥ upper.
  static ConvexPolytope slab(const Eigen::Vector3d& normal, double lower, double upper);

  const std::vector<HalfSpace>& half_spaces() const noexcept { return m_half_spaces; }

  double distance(const Eigen::Vector3d& p) const noexcept {
    double largest = m_half_spaces.front().distance(p);
    for (std::size_t i = 1; i < m_half_spaces.size(); ++i) {
      largest = std::max(largest, m_half_spaces[i].distance(p));
    }
    return largest;
  }
  double distance_and_gradient(const Eigen::Vector3d& p, Eigen::Vector3d& gradient) const noexcept {
    std::size_t best = 0;
    double largest = m_half_spaces.front().distance(p);
    for (std::size_t i = 1; i < m_half_spaces.size(); ++i) {
      const double d = m_half_spaces[i].distance(p);
      if (d > largest) {
        largest = d;
        best = i;
      }
    }
    gradient = m_half_spaces[best].normal();
    return largest;
  }

 private:
  std::vector<HalfSpace> m_half_spaces;
};

/// A ball: ‖p − centre‖ − radius, exact. At the centre the gradient is +x.
class KHZ_CONTACT_API Sphere {
 public:
  /// @param center (m). @param radius (m), > 0.
  /// @throws Error if `center` is not finite or `radius` is not finite and positive.
  Sphere(const Eigen::Vector3d& center, double radius);

  const Eigen::Vector3d& center() const noexcept { return m_center; }
  double radius() const noexcept { return m_radius; }

  /// distance_and_gradient()'s value, from its body (the unused gradient is optimized away), so
  /// the two agree bit for bit.
  double distance(const Eigen::Vector3d& p) const noexcept {
    Eigen::Vector3d unused;
    return distance_and_gradient(p, unused);
  }
  double distance_and_gradient(const Eigen::Vector3d& p, Eigen::Vector3d& gradient) const noexcept {
    const Eigen::Vector3d offset = p - m_center;
    const double length = offset.norm();
    gradient = length > 0.0 ? Eigen::Vector3d(offset / length) : Eigen::Vector3d::UnitX();
    return length - m_radius;
  }

 private:
  Eigen::Vector3d m_center;
  double m_radius;
};

/// An axis-aligned box (rotate it with ImplicitShape's pose). Exact signed distance inside and
/// outside: with q = |p − centre| − half_extents componentwise, ‖max(q, 0)‖ outside and
/// max(q_x, q_y, q_z) inside. The gradient inside is the normal of the nearest face (of the
/// lowest axis where faces are equally near).
class KHZ_CONTACT_API Box {
 public:
  /// @param center (m). @param half_extents half edge lengths along x, y, z (m), each > 0.
  /// @throws Error if a coordinate is not finite or a half extent is not positive.
  Box(const Eigen::Vector3d& center, const Eigen::Vector3d& half_extents);

  const Eigen::Vector3d& center() const noexcept { return m_center; }
  const Eigen::Vector3d& half_extents() const noexcept { return m_half_extents; }

  /// distance_and_gradient()'s value, from its body, so the two agree bit for bit.
  double distance(const Eigen::Vector3d& p) const noexcept {
    Eigen::Vector3d unused;
    return distance_and_gradient(p, unused);
  }
  double distance_and_gradient(const Eigen::Vector3d& p, Eigen::Vector3d& gradient) const noexcept {
    const Eigen::Vector3d local = p - m_center;
    const Eigen::Vector3d q = local.cwiseAbs() - m_half_extents;
    const Eigen::Vector3d sign = local.unaryExpr([](double x) { return x < 0.0 ? -1.0 : 1.0; });
    Eigen::Index axis = 0;
    const double largest = q.maxCoeff(&axis);
    if (largest > 0.0) {  // outside: towards p from its nearest point
      const Eigen::Vector3d outward = q.cwiseMax(0.0);
      const double length = outward.norm();
      gradient = outward.cwiseProduct(sign) / length;
      return length;
    }
    // Inside: the nearest face's normal (the first axis of equal ones, the + face at q = 0).
    gradient = Eigen::Vector3d::Unit(axis) * sign[axis];
    return largest;
  }

 private:
  Eigen::Vector3d m_center;
  Eigen::Vector3d m_half_extents;
};

/// A solid circular cylinder with flat caps, the segment between the caps' centres as its axis.
/// Exact signed distance inside and outside: in the axial half-plane through p, with ρ the
/// distance from the axis line and z the coordinate along it from the middle,
/// q = (ρ − radius, |z| − half_length); ‖max(q, 0)‖ outside, max(q_ρ, q_z) inside. On the axis
/// the radial direction is a fixed unit vector perpendicular to it; where the mantle and a cap
/// are equally near inside, the gradient is the mantle's.
class KHZ_CONTACT_API Cylinder {
 public:
  /// @param cap0, cap1 centres of the two caps (m), distinct. @param radius (m), > 0.
  /// @throws Error if a coordinate is not finite, the caps coincide or the radius is not
  ///         positive.
  Cylinder(const Eigen::Vector3d& cap0, const Eigen::Vector3d& cap1, double radius);

  const Eigen::Vector3d& center() const noexcept { return m_center; }  ///< Midpoint of the axis.
  const Eigen::Vector3d& axis() const noexcept { return m_axis; }      ///< Unit, from cap0 to cap1.
  double radius() const noexcept { return m_radius; }
  double half_length() const noexcept { return m_half_length; }

  double distance(const Eigen::Vector3d& p) const noexcept {
    Eigen::Vector3d unused;
    return distance_and_gradient(p, unused);
  }
  double distance_and_gradient(const Eigen::Vector3d& p, Eigen::Vector3d& gradient) const noexcept {
    const Eigen::Vector3d local = p - m_center;
    const double z = m_axis.dot(local);
    const Eigen::Vector3d radial = local - z * m_axis;
    const double rho = radial.norm();
    const Eigen::Vector3d radial_unit = rho > 0.0 ? Eigen::Vector3d(radial / rho) : m_perpendicular;
    const Eigen::Vector3d axial_unit = z < 0.0 ? Eigen::Vector3d(-m_axis) : m_axis;
    const double q_radial = rho - m_radius;
    const double q_axial = std::abs(z) - m_half_length;
    if (q_radial > 0.0 || q_axial > 0.0) {  // outside
      const double a = std::max(q_radial, 0.0), b = std::max(q_axial, 0.0);
      const double length = std::hypot(a, b);
      gradient = (a * radial_unit + b * axial_unit) / length;
      return length;
    }
    if (q_radial >= q_axial) {
      gradient = radial_unit;
      return q_radial;
    }
    gradient = axial_unit;
    return q_axial;
  }

 private:
  Eigen::Vector3d m_center;
  Eigen::Vector3d m_axis;
  Eigen::Vector3d m_perpendicular;  // the radial direction on the axis
  double m_radius;
  double m_half_length;
};

}  // namespace khz::contact
