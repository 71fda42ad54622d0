#pragma once
// What one contact query returns (thesis §3.5, §3.6.1, §3.12, §4.1–§4.2).

#include <khz/contact/export.hpp>

#include <Eigen/Core>

#include <cstdint>

namespace khz::contact {

/// Counters of one query (thesis Table 3.1's columns).
struct KHZ_CONTACT_API ContactStatistics {
  /// Tree nodes whose point was looked at (copies of a point on deeper levels included).
  std::int64_t nodes_traversed = 0;
  /// Nodes temporal coherence let the traversal skip without looking at their point.
  std::int64_t nodes_skipped = 0;
  /// Whether this query found motion beyond the declared temporal-coherence bounds since the
  /// previous one and dropped every skip (it then visits as a query without coherence would).
  bool coherence_reset = false;
  /// Distinct points in contact (d < 0).
  std::int64_t points_in_contact = 0;
  /// The deepest tree level rendered (−1 before the first query).
  int deepest_level = -1;
  /// False when graceful degradation stopped before a level contact reached.
  bool complete = true;
  /// Wall time of the query (µs, steady clock).
  double microseconds = 0.0;
};

/// Forces of one query, in the world frame. The force and torque act on the haptic object
/// (ContactOptions::haptic_object); the torque is about the grasp point. With ℓ the (weighted)
/// count of points in contact, everything is scaled by L/ℓ once ℓ > L (§3.5).
///
/// The gradients are 3×3, row k the gradient of component k, with respect to a small
/// translation Δx (m) and a small rotation Δω (rad, about the grasp point) of the haptic object,
/// the other object's points and normals seen from the haptic object (§4.2's construction: for
/// a pointshell haptic object these are the gradients in world axes, for a field haptic object
/// in axes that turn with it). ℓ is held fixed in them.
struct KHZ_CONTACT_API ContactResult {
  Eigen::Vector3d force = Eigen::Vector3d::Zero();                  ///< N.
  Eigen::Vector3d torque = Eigen::Vector3d::Zero();                 ///< N·m about the grasp point.
  Eigen::Matrix3d force_by_translation = Eigen::Matrix3d::Zero();   ///< ∂F/∂x, N/m.
  Eigen::Matrix3d force_by_rotation = Eigen::Matrix3d::Zero();      ///< ∂F/∂ω, N/rad.
  Eigen::Matrix3d torque_by_translation = Eigen::Matrix3d::Zero();  ///< ∂T/∂x, N.
  Eigen::Matrix3d torque_by_rotation = Eigen::Matrix3d::Zero();     ///< ∂T/∂ω, N·m/rad.
  /// Σ U_sᵀ f_s over the points in contact of a deformable pointshell, f_s the force on the
  /// point in the pointshell's body frame (§3.6.1): the external reduced force for its
  /// integrator (r_pointshell entries; empty for a rigid pointshell).
  Eigen::VectorXd pointshell_reduced_force;
  /// The reaction on a deformable distance-field object, projected on the modes of the proxy
  /// nearest to each contact (§3.12; empty for a rigid field).
  Eigen::VectorXd field_reduced_force;
  ContactStatistics statistics;
};

}  // namespace khz::contact
