#pragma once
// Coulomb friction at one point of the distributed contact (FrictionOptions): the point's
// tangential anchor, its stick-or-slip force on the field object and that force's derivatives.
// Not part of the public interface: include <khz/contact/query/contact_query.hpp>.

#include <khz/contact/query/contact_options.hpp>
#include <khz/contact/query/detail/cross_matrix.hpp>

#include <Eigen/Core>

#include <cstdint>

namespace khz::contact::detail {

/// Where a point of the pointshell stuck to the field object.
struct FrictionAnchor {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  ///< Field body frame (m).
  /// The query that last found the point in contact (ContactWorkspace's friction count; 0:
  /// none). The anchor holds while no query since then has rendered the point's level.
  std::uint32_t query = 0;
  /// What it did in that query (a sliding point is decided by μ_k, the others by μ_s).
  FrictionState state = FrictionState::none;
};

/// The tangential forces of one query before the L/ℓ scaling, on the field object, world frame.
struct FrictionSums {
  Eigen::Vector3d force = Eigen::Vector3d::Zero();   ///< Σ f_t
  Eigen::Vector3d torque = Eigen::Vector3d::Zero();  ///< Σ r × f_t
  /// [Σ ∂f_t/∂x, Σ ∂f_t/∂ω; Σ ∂(r × f_t)/∂x, Σ ∂(r × f_t)/∂ω] for the motion ContactSums
  /// describes, complete per point (the normal's turn and the lever's included) except the
  /// lever shortening by Δx when the grasp point moves with the field object, which the
  /// traversal adds for the total force.
  Eigen::Matrix<double, 6, 6> jacobian = Eigen::Matrix<double, 6, 6>::Zero();
  std::int64_t sliding = 0;  ///< Points that slid.
};

/// One point in contact: its position x and lever r = x − grasp point (world), inward normal N
/// and field gradient g (world; N under ContactGradient::normal_direction), depth d < 0, normal
/// stiffness c = w k_C and the position in the field's body frame.
struct FrictionPoint {
  Eigen::Vector3d x, lever, normal, gradient, field_point;
  double depth, normal_stiffness;
};

/// The tangential force of `point` on the field object (world), added to `sums` with its
/// derivatives; `anchor` is moved as the point sticks or slides and stamped with `query`.
/// `anchored`: whether the anchor holds (FrictionOptions); if not, the point anchors where it is
/// and adds nothing. World ← field body: `field_rotation`, `field_translation`.
///
/// With s = x − a (a the anchor in the world), P = I − N Nᵀ and k_t = ratio · c, the pull is
/// k_t P s while ‖k_t P s‖ ≤ μ |f_n| (stick; |f_n| = −c d, μ = μ_k if the point slid last time,
/// else μ_s), and otherwise μ_k |f_n| u, u = P s / ‖P s‖ (slip; the anchor is moved to
/// x − μ_k |f_n| / k_t · u). Under the motion of ContactSums (∂x/∂x = −I, ∂x/∂ω = r̃,
/// ∂N/∂ω = Ñ, ∂d/∂x = −gᵀ, ∂d/∂ω = (g × r)ᵀ, the anchor fixed in the field):
///   ∂(P s)/∂x = −P,  ∂(P s)/∂ω = P r̃ − (N·s) Ñ − N (s × N)ᵀ;
///   stick: ∂f/∂· = k_t ∂(P s)/∂·;
///   slip:  ∂f/∂x = μ_k c u gᵀ + μ_k |f_n| (I − u uᵀ)/‖P s‖ ∂(P s)/∂x, likewise for ω with
///          −(g × r)ᵀ;
///   ∂(r × f)/∂x = r̃ ∂f/∂x,  ∂(r × f)/∂ω = r̃ ∂f/∂ω − f̃ r̃.
inline Eigen::Vector3d add_point_friction(const FrictionPoint& point,
                                          const FrictionOptions& friction, bool anchored,
                                          std::uint32_t query,
                                          const Eigen::Matrix3d& field_rotation,
                                          const Eigen::Vector3d& field_translation,
                                          FrictionAnchor& anchor, FrictionSums& sums) noexcept {
  const bool slid_before = anchored && anchor.state == FrictionState::sliding;
  anchor.query = query;
  anchor.state = FrictionState::stuck;
  if (!anchored) {
    anchor.position = point.field_point;
    anchor.state = FrictionState::anchored;
    return Eigen::Vector3d::Zero();
  }
  const Eigen::Vector3d& n = point.normal;
  const Eigen::Vector3d& r = point.lever;
  const Eigen::Vector3d s = point.x - (field_rotation * anchor.position + field_translation);
  const Eigen::Vector3d tangential = s - n.dot(s) * n;  // P s
  const double tangential_stiffness = friction.stiffness_ratio * point.normal_stiffness;
  const double normal_force = -point.normal_stiffness * point.depth;  // |f_n|
  const double limit =
      (slid_before ? friction.kinetic_coefficient : friction.static_coefficient) * normal_force;

  const Eigen::Matrix3d projector = Eigen::Matrix3d::Identity() - n * n.transpose();
  const Eigen::Matrix3d lever_cross = cross_matrix(r);
  const Eigen::Matrix3d by_rotation =  // ∂(P s)/∂ω
      projector * lever_cross - n.dot(s) * cross_matrix(n) - n * s.cross(n).transpose();

  Eigen::Vector3d f;
  Eigen::Matrix3d f_by_translation, f_by_rotation;
  if (tangential_stiffness * tangential.norm() <= limit) {
    f = tangential_stiffness * tangential;
    f_by_translation = -tangential_stiffness * projector;
    f_by_rotation = tangential_stiffness * by_rotation;
  } else {
    const double length = tangential.norm();
    const Eigen::Vector3d u = tangential / length;
    const double pull = friction.kinetic_coefficient * normal_force;
    const double pull_by_depth = friction.kinetic_coefficient * point.normal_stiffness;  // −∂/∂d
    const Eigen::Matrix3d turn =
        (pull / length) * (Eigen::Matrix3d::Identity() - u * u.transpose());
    f = pull * u;
    f_by_translation = pull_by_depth * u * point.gradient.transpose() - turn * projector;
    f_by_rotation = -pull_by_depth * u * point.gradient.cross(r).transpose() + turn * by_rotation;
    anchor.position =
        point.field_point - field_rotation.transpose() * (pull / tangential_stiffness * u);
    anchor.state = FrictionState::sliding;
    ++sums.sliding;
  }
  sums.force += f;
  sums.torque += r.cross(f);
  sums.jacobian.topLeftCorner<3, 3>() += f_by_translation;
  sums.jacobian.topRightCorner<3, 3>() += f_by_rotation;
  sums.jacobian.bottomLeftCorner<3, 3>() += lever_cross * f_by_translation;
  sums.jacobian.bottomRightCorner<3, 3>() +=
      lever_cross * f_by_rotation - cross_matrix(f) * lever_cross;
  return f;
}

}  // namespace khz::contact::detail
