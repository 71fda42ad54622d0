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
  /// The pair's total normal load Σ|f_n| (N, before L/ℓ) that the anchor's stretch was last
  /// measured against (add_point_friction()'s pair_load; 0: none yet).
  double load = 0.0;
  /// The query that last found the point in contact (ContactWorkspace's friction count; 0:
  /// none). The anchor holds while no query since then has rendered the point's level.
  std::uint32_t query = 0;
  /// What it did in that query (a sliding point is decided by μ_k, the others by μ_s).
  FrictionState state = FrictionState::none;
};

/// The tangential forces of one query before the L/ℓ scaling, on the field object, world frame,
/// and what their derivatives are assembled from (jacobian()).
///
/// Per point, with k the point's effective stiffness (f = k P s: k_t sticking, μ_k |f_n| / ‖P s‖
/// sliding) and w = N × r + s × N, the derivatives of add_point_friction() expand, by
/// P r̃ = r̃ − N (N × r)ᵀ and ã b̃ = b aᵀ − (a·b) 1, into
///   ∂f/∂x = −k 1 + k N Nᵀ
///   ∂f/∂ω = (k r)~ − (k (N·s) N)~ − k N wᵀ
///   ∂T/∂x = −(k r)~ + k (r × N) Nᵀ
///   ∂T/∂ω = k (r × N)(−w)ᵀ + r (k r − f)ᵀ − k (N·s) N rᵀ + (−k r·r + k (N·s)(r·N) + f·r) 1
/// and one more rank-one term for the force's change with depth, [v; r × v] [κ g; −κ g × r]ᵀ:
/// sticking, v = P s and κ = μ_s c / δ (k_t grows with depth); sliding, v = u and κ = μ_k c
/// (the pull's fixed length), where a sliding point adds [u; r × u] [k u; k (N·s)(u × N)
/// − k u × r]ᵀ too. So a point adds two rank-one updates (three sliding), two vectors and three
/// numbers; the cross matrices and the identity terms are formed once, in jacobian().
struct FrictionSums {
  Eigen::Vector3d force = Eigen::Vector3d::Zero();   ///< Σ f_t
  Eigen::Vector3d torque = Eigen::Vector3d::Zero();  ///< Σ r × f_t
  double stiffness = 0.0;                            ///< Σ k
  double diagonal = 0.0;                             ///< Σ (−k r·r + k (N·s)(r·N) + f·r)
  Eigen::Vector3d lever = Eigen::Vector3d::Zero();   ///< Σ k r
  Eigen::Vector3d offset = Eigen::Vector3d::Zero();  ///< Σ k (N·s) N
  /// Σ k [N; r × N] [N; −w]ᵀ, plus the sliding points' rank-one terms.
  Eigen::Matrix<double, 6, 6> moments = Eigen::Matrix<double, 6, 6>::Zero();
  Eigen::Matrix3d lever_moments = Eigen::Matrix3d::Zero();  ///< Σ r (k r − f)ᵀ − k (N·s) N rᵀ
  std::int64_t sliding = 0;                                 ///< Points that slid.
  double normal_load = 0.0;  ///< Σ|f_n| (N): the next query's pair_load.

  /// [Σ ∂f_t/∂x, Σ ∂f_t/∂ω; Σ ∂(r × f_t)/∂x, Σ ∂(r × f_t)/∂ω] for the motion ContactSums
  /// describes, complete per point (the normal's turn and the lever's included) except the
  /// lever shortening by Δx when the grasp point moves with the field object, which the
  /// traversal adds for the total force.
  Eigen::Matrix<double, 6, 6> jacobian() const noexcept {
    Eigen::Matrix<double, 6, 6> j = moments;
    j.topLeftCorner<3, 3>().diagonal().array() -= stiffness;
    j.topRightCorner<3, 3>() += cross_matrix(lever - offset);
    j.bottomLeftCorner<3, 3>() -= cross_matrix(lever);
    j.bottomRightCorner<3, 3>() += lever_moments;
    j.bottomRightCorner<3, 3>().diagonal().array() += diagonal;
    return j;
  }
};

/// One point in contact: its position x and lever r = x − grasp point (world), inward normal N
/// and field gradient g (world; N under ContactGradient::normal_direction), depth d < 0, normal
/// stiffness c = w k_C (both through the contact onset, ContactOnset: |f_n| = −c d) and the
/// position in the field's body frame.
struct FrictionPoint {
  Eigen::Vector3d x, lever, normal, gradient, field_point;
  double depth, normal_stiffness;
};

/// The tangential force of `point` on the field object (world), added to `sums` with its
/// derivatives; `anchor` is moved as the point sticks or slides and stamped with `query`.
/// `anchored`: whether the anchor holds (FrictionOptions); if not, the point anchors where it is
/// and adds nothing. World ← field body: `field_rotation`, `field_translation`. `pair_load`: the
/// pair's total normal load Σ|f_n| in its last query (N, before L/ℓ; 0 before the first).
///
/// A held anchor is first brought to the contact's load: when `pair_load` exceeds the load its
/// stretch was last measured against (FrictionAnchor::load), the stretch P s shrinks by their
/// ratio, so that the spring keeps its pull as k_t grows (a contact pressed harder while stuck
/// keeps its tangential force, as in Mindlin and Deresiewicz's elastic spheres) and stores no
/// energy the hand did not put in. The pair's total decides, not the point's own load: a load
/// that only shifts between points (a pushed block rocking onto its front edge) rescales nothing,
/// so every point still gives δ before it slides. The ratio comes from earlier queries, so the
/// derivatives below hold as they are, for the anchor so moved.
///
/// With s = x − a (a the anchor in the world), P = I − N Nᵀ, |f_n| = −c d and
/// k_t = μ_s |f_n| / δ (δ = FrictionOptions::stick_distance), the pull is k_t P s while
/// ‖k_t P s‖ ≤ μ |f_n|, i.e. ‖P s‖ ≤ μ δ / μ_s (stick; μ = μ_k if the point slid last time, else
/// μ_s), and otherwise μ_k |f_n| u, u = P s / ‖P s‖ (slip; the anchor is moved to
/// x − (μ_k / μ_s) δ u). Under the motion of ContactSums (∂x/∂x = −I, ∂x/∂ω = r̃,
/// ∂N/∂ω = Ñ, ∂d/∂x = −gᵀ, ∂d/∂ω = (g × r)ᵀ, the anchor fixed in the field):
///   ∂(P s)/∂x = −P,  ∂(P s)/∂ω = P r̃ − (N·s) Ñ − N (s × N)ᵀ;
///   stick: ∂f/∂x = k_t ∂(P s)/∂x + (μ_s c / δ) P s gᵀ, likewise for ω with −(g × r)ᵀ;
///   slip:  ∂f/∂x = μ_k c u gᵀ + μ_k |f_n| (I − u uᵀ)/‖P s‖ ∂(P s)/∂x, likewise for ω with
///          −(g × r)ᵀ;
///   ∂(r × f)/∂x = r̃ ∂f/∂x,  ∂(r × f)/∂ω = r̃ ∂f/∂ω − f̃ r̃.
inline Eigen::Vector3d add_point_friction(const FrictionPoint& point,
                                          const FrictionOptions& friction, bool anchored,
                                          std::uint32_t query, double pair_load,
                                          const Eigen::Matrix3d& field_rotation,
                                          const Eigen::Vector3d& field_translation,
                                          FrictionAnchor& anchor, FrictionSums& sums) noexcept {
  const bool slid_before = anchored && anchor.state == FrictionState::sliding;
  anchor.query = query;
  anchor.state = FrictionState::stuck;
  sums.normal_load += -point.normal_stiffness * point.depth;
  const double stretched_under = anchor.load;
  anchor.load = pair_load;
  if (!anchored) {
    anchor.position = point.field_point;
    anchor.state = FrictionState::anchored;
    return Eigen::Vector3d::Zero();
  }
  const Eigen::Vector3d& n = point.normal;
  const Eigen::Vector3d& r = point.lever;
  Eigen::Vector3d s = point.x - (field_rotation * anchor.position + field_translation);
  Eigen::Vector3d tangential = s - n.dot(s) * n;  // P s
  if (stretched_under > 0.0 && pair_load > stretched_under) {
    // The contact was pressed harder: keep the pull it had (Mindlin-Deresiewicz), so that the
    // stiffer springs store nothing the hand did not put in.
    const double shrink = 1.0 - stretched_under / pair_load;
    anchor.position += field_rotation.transpose() * (shrink * tangential);
    s -= shrink * tangential;
    tangential -= shrink * tangential;
  }
  // k_t ∝ |f_n|: every point reaches its cone after the same give δ, so a rigid push breaks
  // the whole contact loose at μ_s Σ|f_n| however the load is spread over its points.
  const double stiffness_by_depth =
      friction.static_coefficient * point.normal_stiffness / friction.stick_distance;  // −∂k_t/∂d
  const double normal_force = -point.normal_stiffness * point.depth;                   // |f_n|
  const double tangential_stiffness = stiffness_by_depth * -point.depth;               // k_t
  const double limit =
      (slid_before ? friction.kinetic_coefficient : friction.static_coefficient) * normal_force;

  const double length = tangential.norm();
  const double normal_offset = n.dot(s);  // N·s
  double k = tangential_stiffness;
  // The force's change with depth, [v; r × v] [κ g; −κ g × r]ᵀ (FrictionSums), and sliding,
  // the pull's fixed length.
  Eigen::Matrix<double, 6, 1> left, right;
  if (tangential_stiffness * length > limit) {
    // Slides: held at μ_k |f_n| along u, its anchor dragged to that spring length behind it.
    const Eigen::Vector3d u = tangential / length;
    const double pull = friction.kinetic_coefficient * normal_force;
    const double pull_by_depth = friction.kinetic_coefficient * point.normal_stiffness;  // −∂/∂d
    k = pull / length;
    left << u, r.cross(u);
    right << k * u + pull_by_depth * point.gradient,
        k * (normal_offset * u.cross(n) - u.cross(r)) - pull_by_depth * point.gradient.cross(r);
    const double spring_length =
        friction.kinetic_coefficient / friction.static_coefficient * friction.stick_distance;
    anchor.position = point.field_point - field_rotation.transpose() * (spring_length * u);
    anchor.state = FrictionState::sliding;
    ++sums.sliding;
  } else {
    left << tangential, r.cross(tangential);
    right << stiffness_by_depth * point.gradient, -stiffness_by_depth * point.gradient.cross(r);
  }
  sums.moments.noalias() += left * right.transpose();
  const Eigen::Vector3d f = k * tangential;
  const Eigen::Vector3d w = n.cross(r) + s.cross(n);
  left << k * n, k * r.cross(n);
  right << n, -w;
  sums.moments.noalias() += left * right.transpose();
  sums.lever_moments.noalias() +=
      r * (k * r - f).transpose() - (k * normal_offset) * n * r.transpose();
  sums.force += f;
  sums.torque += r.cross(f);
  sums.stiffness += k;
  sums.diagonal += -k * r.squaredNorm() + k * normal_offset * r.dot(n) + f.dot(r);
  sums.lever += k * r;
  sums.offset += (k * normal_offset) * n;
  return f;
}

}  // namespace khz::contact::detail
