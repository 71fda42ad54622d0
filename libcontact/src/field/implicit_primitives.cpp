#include <khz/contact/field/implicit_primitives.hpp>

#include <Eigen/Geometry>

#include <string>
#include <utility>

namespace khz::contact {
namespace {

void require_finite(const Eigen::Vector3d& v, const char* what) {
  if (!v.allFinite()) throw Error(std::string(what) + " is not finite");
}

void require_positive(double value, const char* what) {
  if (!(std::isfinite(value) && value > 0.0)) {
    throw Error(std::string(what) + " must be finite and positive, got " + std::to_string(value));
  }
}

Eigen::Vector3d unit_normal(const Eigen::Vector3d& normal, const char* what) {
  require_finite(normal, what);
  const double length = normal.norm();
  if (!(length > 0.0)) throw Error(std::string(what) + " is zero");
  return normal / length;
}

}  // namespace

HalfSpace::HalfSpace(const Eigen::Vector3d& normal, double offset)
    : m_normal(unit_normal(normal, "HalfSpace: the normal")), m_offset(offset) {
  if (!std::isfinite(offset)) throw Error("HalfSpace: the offset is not finite");
}

HalfSpace HalfSpace::through(const Eigen::Vector3d& point, const Eigen::Vector3d& normal) {
  require_finite(point, "HalfSpace: the point");
  const Eigen::Vector3d n = unit_normal(normal, "HalfSpace: the normal");
  return {n, n.dot(point)};
}

ConvexPolytope::ConvexPolytope(std::vector<HalfSpace> half_spaces)
    : m_half_spaces(std::move(half_spaces)) {
  if (m_half_spaces.empty()) throw Error("ConvexPolytope: no half-space");
}

ConvexPolytope ConvexPolytope::slab(const Eigen::Vector3d& normal, double lower, double upper) {
  const Eigen::Vector3d n = unit_normal(normal, "ConvexPolytope::slab: the normal");
  if (!(std::isfinite(lower) && std::isfinite(upper) && lower < upper)) {
    throw Error("ConvexPolytope::slab: need finite bounds lower < upper, got " +
                std::to_string(lower) + " and " + std::to_string(upper));
  }
  return ConvexPolytope({HalfSpace(n, upper), HalfSpace(-n, -lower)});
}

Sphere::Sphere(const Eigen::Vector3d& center, double radius) : m_center(center), m_radius(radius) {
  require_finite(center, "Sphere: the centre");
  require_positive(radius, "Sphere: the radius");
}

Box::Box(const Eigen::Vector3d& center, const Eigen::Vector3d& half_extents)
    : m_center(center), m_half_extents(half_extents) {
  require_finite(center, "Box: the centre");
  require_positive(half_extents.x(), "Box: the half extent along x");
  require_positive(half_extents.y(), "Box: the half extent along y");
  require_positive(half_extents.z(), "Box: the half extent along z");
}

Cylinder::Cylinder(const Eigen::Vector3d& cap0, const Eigen::Vector3d& cap1, double radius)
    : m_radius(radius) {
  require_finite(cap0, "Cylinder: the first cap centre");
  require_finite(cap1, "Cylinder: the second cap centre");
  require_positive(radius, "Cylinder: the radius");
  const Eigen::Vector3d axis = cap1 - cap0;
  m_half_length = 0.5 * axis.norm();
  if (!(m_half_length > 0.0)) throw Error("Cylinder: the cap centres coincide");
  m_center = 0.5 * (cap0 + cap1);
  m_axis = axis / axis.norm();
  // Any unit vector perpendicular to the axis: cross it with the coordinate axis least aligned.
  Eigen::Index least = 0;
  m_axis.cwiseAbs().minCoeff(&least);
  m_perpendicular = m_axis.cross(Eigen::Vector3d::Unit(least)).normalized();
}

}  // namespace khz::contact
