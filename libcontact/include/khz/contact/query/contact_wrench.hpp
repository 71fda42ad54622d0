#pragma once
// The part of a contact result the coupling needs (thesis §4.1–§4.2): force, torque, their four
// gradients and the query's counters. What a multi-body cycle sums over the pairs a held object
// is in, and what a cycle record keeps.

#include <khz/contact/export.hpp>

#include <Eigen/Core>

#include <cstdint>

namespace khz::contact {

/// Counters of one query (thesis Table 3.1's columns), or of several summed by accumulate().
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
  /// Of those, the points whose friction slid this query (0 without friction): the others in
  /// contact stuck, or entered contact (FrictionOptions).
  std::int64_t points_sliding = 0;
  /// The deepest tree level rendered (−1 before the first query).
  int deepest_level = -1;
  /// How far the deepest point in contact is inside the field: −min d over the points in
  /// contact (m, distance-field units); 0 without contact.
  double deepest_penetration = 0.0;
  /// False when graceful degradation stopped before a level contact reached.
  bool complete = true;
  /// Wall time of the query (µs, steady clock or DegradationOptions::clock).
  double microseconds = 0.0;

  /// Combines another query's counters into these, as for queries run one after the other in
  /// one cycle: counts and µs add, the deepest level and penetration are the larger, complete only
  /// if both are, reset if either reset.
  void accumulate(const ContactStatistics& other) noexcept;
};

/// Force and torque on a haptic object from contact, with their gradients, in the world frame
/// (§4.2). The torque is about the grasp point. The gradients are 3×3, row k the gradient of
/// component k, with respect to a small translation Δx (m) and a small rotation Δω (rad, about
/// the grasp point) of the haptic object, the other objects' points and normals seen from the
/// haptic object (§4.2's construction: for a pointshell haptic object these are the gradients in
/// world axes, for a field haptic object in axes that turn with it). What VirtualCoupling::step()
/// reads.
struct KHZ_CONTACT_API ContactWrench {
  Eigen::Vector3d force = Eigen::Vector3d::Zero();                  ///< N.
  Eigen::Vector3d torque = Eigen::Vector3d::Zero();                 ///< N·m about the grasp point.
  Eigen::Matrix3d force_by_translation = Eigen::Matrix3d::Zero();   ///< ∂F/∂x, N/m.
  Eigen::Matrix3d force_by_rotation = Eigen::Matrix3d::Zero();      ///< ∂F/∂ω, N/rad.
  Eigen::Matrix3d torque_by_translation = Eigen::Matrix3d::Zero();  ///< ∂T/∂x, N.
  Eigen::Matrix3d torque_by_rotation = Eigen::Matrix3d::Zero();     ///< ∂T/∂ω, N·m/rad.
  ContactStatistics statistics;

  /// Adds another wrench on the same haptic object, about the same grasp point and for the same
  /// motion (each pair's query of one held object gives such): forces, torques and gradients
  /// add, the statistics combine (ContactStatistics::accumulate()). noexcept, no allocation.
  void accumulate(const ContactWrench& other) noexcept;
};

}  // namespace khz::contact
