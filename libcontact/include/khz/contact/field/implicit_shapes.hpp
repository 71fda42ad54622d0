#pragma once
// Analytic implicit obstacles for the contact query (thesis §3.11.1): a primitive placed
// rigidly in the world, and unions of them. Value types holding a std::variant, so a query costs
// a jump, never a virtual call or an allocation.

#include <khz/contact/common.hpp>
#include <khz/contact/export.hpp>
#include <khz/contact/field/implicit_primitives.hpp>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <concepts>
#include <type_traits>
#include <utility>
#include <variant>
#include <vector>

namespace khz::contact {

/// One of the analytic primitives, in its own (body) frame.
using ImplicitPrimitive = std::variant<HalfSpace, ConvexPolytope, Sphere, Box, Cylinder>;

/// A primitive moved rigidly: its signed distance at p is the primitive's at pose⁻¹·p (a rigid
/// motion preserves distances, so exactness carries over), its gradient the primitive's rotated
/// into the world. Satisfies DistanceField (metres, negative inside); copying it may allocate
/// (a ConvexPolytope's planes), querying never does.
class KHZ_CONTACT_API ImplicitShape {
 public:
  /// The primitive (a HalfSpace, Sphere, …, or an ImplicitPrimitive) where its parameters put
  /// it. Implicit, so that a primitive stands wherever a shape is expected (e.g. in the list of
  /// an ImplicitUnion).
  template <typename Primitive>
  requires std::constructible_from<ImplicitPrimitive, Primitive&&> &&
      (!std::same_as<std::remove_cvref_t<Primitive>, ImplicitShape>)
          ImplicitShape(Primitive&& primitive)  // NOLINT(google-explicit-constructor)
      : m_primitive(std::forward<Primitive>(primitive)),
        m_rotation(Eigen::Matrix3d::Identity()),
        m_translation(Eigen::Vector3d::Zero()) {}
  /// The primitive moved by `pose` (body to world: p_world = R p_body + t).
  /// @throws Error unless `pose` is finite and its linear part a rotation (orthonormal within
  ///         1e-9, determinant +1).
  ImplicitShape(ImplicitPrimitive primitive, const Eigen::Isometry3d& pose);

  const ImplicitPrimitive& primitive() const noexcept { return m_primitive; }
  /// Body to world.
  Eigen::Isometry3d pose() const noexcept;

  double distance(const Eigen::Vector3d& p) const noexcept {
    const Eigen::Vector3d body = m_rotation.transpose() * (p - m_translation);
    return std::visit([&](const auto& primitive) noexcept { return primitive.distance(body); },
                      m_primitive);
  }
  double distance_and_gradient(const Eigen::Vector3d& p, Eigen::Vector3d& gradient) const noexcept {
    const Eigen::Vector3d body = m_rotation.transpose() * (p - m_translation);
    Eigen::Vector3d body_gradient;
    const double d = std::visit(
        [&](const auto& primitive) noexcept {
          return primitive.distance_and_gradient(body, body_gradient);
        },
        m_primitive);
    gradient = m_rotation * body_gradient;
    return d;
  }

 private:
  ImplicitPrimitive m_primitive;
  Eigen::Matrix3d m_rotation;
  Eigen::Vector3d m_translation;
};

/// The union of shapes: min_i d_i(p), the gradient of the minimizing shape (the first of equal
/// ones). Exact outside the union (the distance to a union is the least distance to its parts);
/// inside, where parts overlap, the depth is that of the deepest single part, which can be less
/// than the depth below the union's boundary. Satisfies DistanceField; the shapes are stored at
/// construction, queries allocate nothing.
class KHZ_CONTACT_API ImplicitUnion {
 public:
  /// @throws Error if `shapes` is empty.
  explicit ImplicitUnion(std::vector<ImplicitShape> shapes);

  const std::vector<ImplicitShape>& shapes() const noexcept { return m_shapes; }

  double distance(const Eigen::Vector3d& p) const noexcept {
    double least = m_shapes.front().distance(p);
    for (std::size_t i = 1; i < m_shapes.size(); ++i) {
      least = std::min(least, m_shapes[i].distance(p));
    }
    return least;
  }
  double distance_and_gradient(const Eigen::Vector3d& p, Eigen::Vector3d& gradient) const noexcept {
    double least = m_shapes.front().distance_and_gradient(p, gradient);
    Eigen::Vector3d candidate;
    for (std::size_t i = 1; i < m_shapes.size(); ++i) {
      const double d = m_shapes[i].distance_and_gradient(p, candidate);
      if (d < least) {
        least = d;
        gradient = candidate;
      }
    }
    return least;
  }

 private:
  std::vector<ImplicitShape> m_shapes;
};

}  // namespace khz::contact
