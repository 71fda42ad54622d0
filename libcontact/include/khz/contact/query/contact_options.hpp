#pragma once
// What a contact query is asked to do: the penalty model (thesis §3.5), the force gradients
// (§4.2), graceful degradation (§3.10.3) and temporal coherence (§3.10.2).

#include <khz/contact/common.hpp>
#include <khz/contact/export.hpp>

namespace khz::contact {

/// Which of the two objects the user holds: the query reports the force and torque on it, and
/// their gradients with respect to its motion. The thesis holds the distance-field object
/// (§4.1); the other choice only flips the signs of the force and torque.
enum class HapticObject { distance_field, pointshell };

/// How ∂d/∂p enters the force gradients (§4.2).
enum class ContactGradient {
  /// The field's own gradient (eq. 4.5–4.8): the exact derivative of the force the query
  /// returns wherever the field is differentiable.
  field_gradient,
  /// ∂d/∂p ≈ N, the point's normal (eq. 4.11–4.12), as the thesis ran it: no gradient lookup,
  /// and no noise from the field's gradient jumping across cells or medial axes.
  normal_direction,
};

/// Graceful degradation (§3.10.3): the traversal renders level after level, and a query that
/// stops early returns exactly what the levels it completed found (as with max_level).
///
/// node_count mode decides before entering level i+1 from its predicted cost, eq. 3.13:
///   α (V_traversed + V_queued) + β (V_contact + V_contact / V_traversed · V_queued)
/// (α = 1, β = contact_weight), entering it only if the prediction stays within the threshold:
/// the warm one for levels no deeper than the deepest level of the previous query, the cold one,
/// cold_fraction × warm, below it (so the level of detail does not flicker).
///
/// time_budget mode does not predict: it enters the next level while time is left, reads the
/// clock every 32 nodes of it, and abandons the level the moment the query has run longer than
/// the budget (warm levels) or cold_fraction of it (deeper levels), returning the levels before
/// it. So it never cuts a query that fits its budget at the previous query's level of detail,
/// goes finer only with room to spare, and overruns by at most one clock interval (a few µs).
///
/// A contact floor overrides both: when the previous query had points in contact, every level
/// but its deepest is rendered again whatever the cost, and its deepest too while it fits
/// (node_count: the warm threshold; time_budget: the budget at the machine's typical cost per
/// unit, which a stall barely moves). So a contact is handed to a coarser level at most one
/// level per query, and not at all because of a spike in the measured cost: never at once to a
/// coarse level whose few points could let the object sink through a thin wall. A query whose
/// contact has grown can exceed its budget by the cost of its second-deepest level's growth for
/// one query.
struct KHZ_CONTACT_API DegradationOptions {
  enum class Mode {
    none,        ///< Every level, as deep as contact reaches.
    node_count,  ///< Thresholds in cost units: warm_threshold (V_W of §3.10.3).
    /// A budget in time, budget_microseconds per query: each level is rendered if the query
    /// completes it within the budget (cold_fraction of it for a level deeper than the previous
    /// query's), and abandoned when it cannot (the contact floor aside).
    time_budget,
  };
  Mode mode = Mode::none;
  /// V_W in cost units (nodes traversed when contact_weight = 0); node_count mode, > 0.
  double warm_threshold = 2500.0;
  /// µs per query; time_budget mode, > 0.
  double budget_microseconds = 250.0;
  /// V_C / V_W, in (0, 1] (the thesis uses 0.8); in time_budget mode the fraction of the
  /// budget a level deeper than the previous query's must fit in.
  double cold_fraction = 0.8;
  /// β/α of eq. 3.13: the extra cost of a point in contact (normal, force, gradients, reduced
  /// force) in units of a traversed node, ≥ 0; the thesis suggests up to 1.5, and counts
  /// traversed nodes only (0). In time_budget mode it weighs the typical cost per unit the
  /// contact floor measures.
  double contact_weight = 0.0;
  /// The clock a time budget is measured on: seconds from any origin, never decreasing; null
  /// (the default) is the steady clock. Read at a query's start, after each level, every 32
  /// nodes of a level the budget may cut, and at its end (ContactStatistics::microseconds).
  /// For simulating a slower or stalling machine in tests, or for driving the budget from
  /// another time source.
  double (*clock)() noexcept = nullptr;
};

/// Temporal coherence (§3.10.2): a node whose bounding sphere was a gap g away from contact is
/// not visited again until motion could have closed the gap. The caller declares how far, per
/// query, the pointshell may move relative to the field object and how far a deformable field
/// object's surface may move; then no point comes closer to the surface by more than
///   translation + rotation · ρ + deformation + field_deformation   (m per query)
/// with ρ the farthest any point is from the pointshell's reference point (the centre of its
/// rest bounding box; for a deformable pointshell plus max_s ‖U_s‖·‖q‖). Each query measures the
/// motion that actually happened since the previous one (the relative pose; a deformable
/// pointshell's max_s ‖U_s‖·‖Δq‖; a deformed field's displacement_bound()·‖Δq‖); if it exceeds a
/// declared bound, every cached skip is dropped before the traversal
/// (ContactStatistics::coherence_reset). So a skipped node is never in contact — given a field
/// that changes no faster than the distance moved, as a distance function does and the culling
/// test itself assumes. For a deformed distance field (§3.12) that holds for the distance to the
/// deformed surface, which the field approximates: its proxy blend can change faster where the
/// set of nearest proxies shifts, so there a skipped node may rarely touch the approximation
/// (bench_contact_query counts how often the forces differ).
struct KHZ_CONTACT_API CoherenceOptions {
  bool enabled = false;
  /// Largest motion (m) per query of the pointshell's reference point in the field's frame.
  double max_translation = 0.0;
  /// Largest relative rotation (rad) per query.
  double max_rotation = 0.0;
  /// Largest deformation displacement (m) per query of any pointshell point (0 for rigid ones).
  double max_deformation = 0.0;
  /// Largest displacement (m) per query of a deformable field object's surface (0 for rigid
  /// ones). Against a deformable field without BoundedDeformableDistanceField's bound, the
  /// query does not skip.
  double max_field_deformation = 0.0;
  /// Largest number of queries a node is skipped for, ≥ 1 (then it is looked at again).
  int max_skip = 4096;
};

/// Coulomb friction on the distributed contact (beyond the thesis, which names friction as its
/// open problem, §5; issue 20). Each point in contact holds a tangential anchor, the spot of the
/// field object where it stuck (Hayward and Armstrong's adhesion-point model of friction for
/// haptic rendering, applied per point): the point is pulled back to it in the tangent plane
/// (normal N) by a spring of stiffness k_t = μ_s |f_n| / stick_distance (f_n = w k_C d N, the
/// point's normal force), and when that pull would exceed μ |f_n| the point slides: the pull is
/// held at μ_k |f_n| and the anchor is dragged along to that distance behind it. A sliding point
/// uses μ_k, a stuck one μ_s, to decide (so μ_s > μ_k gives stick–slip). As k_t grows with the
/// point's load, every point in contact gives the same distance before it slides, so a contact
/// pushed as a whole breaks loose at μ_s times its whole normal force however unevenly that is
/// shared (with a spring as stiff at every point, lightly loaded points would slide first and
/// the contact give way below it). The model is a
/// spring with no velocity, so it holds a load at rest without drift, needs no rate-dependent
/// tuning, and its force and all four gradients are exact derivatives (ContactResult says of
/// what). It dissipates: a stuck point returns what it stored, a sliding one loses it, and a
/// contact pressed harder while stuck keeps its pull (each stuck point's stretch shrinks by the
/// ratio of the pair's total normal load, as Mindlin and Deresiewicz's elastic spheres keep
/// their tangential force), so that its stiffening springs store nothing the hand did not put
/// in. A load that only shifts between points rescales nothing. (The total is the last query's,
/// one cycle late; and a load shifting between stuck points stretched unequally still stores
/// ½ Σ Δk_t s², which cancels when their stretches s are equal, as in a rigid push.)
///
/// Anchors live in the workspace (no allocation per query) and are kept per point of the
/// pointshell, in the field object's body frame:
/// - a point entering contact anchors where it is: no tangential force in that query;
/// - a point looked at and in contact keeps (stick) or drags (slip) its anchor;
/// - a point of a level the query rendered but found out of contact (looked at with d ≥ 0, or
///   in a culled subtree, or skipped by temporal coherence, which skips only points apart from
///   the surface) loses its anchor;
/// - a point of a level graceful degradation did not render keeps its anchor until a query
///   renders that level again, and then continues from it (stick or slip);
/// - ContactWorkspace::reset() and set_options() drop every anchor.
/// Against a deformed field (§3.12) the anchor is fixed in the field's body frame, not to the
/// material: a field that deforms moves its surface under the anchors.
struct KHZ_CONTACT_API FrictionOptions {
  /// μ_s ≥ 0: a stuck point slides once its tangential pull exceeds μ_s |f_n|. 0 (the default)
  /// turns friction off: no anchors are kept and the query is the thesis's.
  double static_coefficient = 0.0;
  /// μ_k in [0, μ_s]: the pull of a sliding point, μ_k |f_n|, and the limit under which it
  /// sticks again.
  double kinetic_coefficient = 0.0;
  /// δ (m): how far a stuck point moves along the surface from its anchor before it slides
  /// (the presliding displacement, Hayward and Armstrong's z_max); the anchor spring's stiffness
  /// per point is μ_s |f_n| / δ. Smaller is stiffer: a stuck point is as stiff sideways as into
  /// the surface when δ = μ_s |d|, and stiffer below that depth.
  /// 0 (the default) chooses δ = μ_s h per query, h the voxel of the field queried (its
  /// cell_size(), CellSizedDistanceField): with saturation a contact at rest is pressed in up to
  /// h/2 (§4.9), so no stuck point is stiffer sideways than half its normal stiffness and the
  /// whole contact stays within the w k_C bound the L/ℓ scaling keeps (§3.5, §4.7).
  /// docs/CONTACT.md shows a tight ball-and-socket contact that loses its passivity with anchors
  /// ten times stiffer. A field without a voxel (an analytic shape) has no such default: give
  /// δ > 0, or the query refuses (returns false).
  double stick_distance = 0.0;

  /// δ for a field of voxel `cell_size` (m): stick_distance if given (> 0), else
  /// μ_s × cell_size (0 when cell_size is 0: no voxel to choose it from).
  double stick_distance_for(double cell_size) const noexcept {
    return stick_distance > 0.0 ? stick_distance : static_coefficient * cell_size;
  }

  /// Whether friction is on (μ_s > 0).
  bool enabled() const noexcept { return static_coefficient > 0.0; }
};

/// What friction did at a point in the last query (FrictionOptions).
enum class FrictionState {
  none,      ///< Not in contact in the last query, or friction off.
  anchored,  ///< Entered contact: anchored where it is, no tangential force yet.
  stuck,     ///< Held by its anchor: the pull is within the friction cone.
  sliding,   ///< Slid: pulled by μ_k |f_n|, its anchor dragged along.
};

/// The whole configuration of a contact query.
struct KHZ_CONTACT_API ContactOptions {
  /// k_C (N/m) of eq. 3.1, > 0.
  double stiffness = 1000.0;
  /// L of §3.5, > 0: when the (weighted) count ℓ of points in contact exceeds L the total force,
  /// torque and gradients are scaled by L/ℓ, so stiffness stays bounded however many points
  /// touch (the thesis uses 10).
  double scaling_count = 10.0;
  /// Deepest tree level to render, or −1 for all: a fixed level of detail (e.g. to measure the
  /// force error per level, §3.5.1).
  int max_level = -1;
  HapticObject haptic_object = HapticObject::distance_field;
  ContactGradient gradient = ContactGradient::field_gradient;
  /// δ (m) of the contact onset (beyond the thesis): a point shallower than δ pushes with
  /// w k_C d²/(2δ) and counts −d/δ of its weight w in ℓ; a deeper one pushes with
  /// w k_C (|d| − δ/2) and counts w. So a point's force, its stiffness and its share of ℓ all
  /// grow continuously from zero as it enters contact, where eq. 3.1's step count makes the
  /// L/ℓ-scaled force jump by about 1/ℓ of itself whenever a point enters or leaves (the
  /// chatter docs/HAPTICS.md measures). A contact pressed uniformly less than δ deep is half as
  /// stiff (L k_C / 2 once ℓ > L); deeper it rests δ/2 deeper than under eq. 3.1. The force's
  /// gradients hold ℓ fixed: ℓ's own change would add a non-symmetric term, with which the
  /// coupling's linearised step turned contacts unstable (measured, docs/HAPTICS.md).
  /// 0 (the default) chooses δ = onset_voxels × h per query, h the voxel of the field queried
  /// (its cell_size(), CellSizedDistanceField); a field without a voxel (an analytic shape)
  /// then gets δ = 0, eq. 3.1 exactly.
  double onset_depth = 0.0;
  /// δ in voxels of the field queried when onset_depth is 0, ≥ 0; 0 turns the onset off
  /// (eq. 3.1). The default, 0.1, took every rigid bundled scene's contact-force jump p99 to
  /// 0.2–2.4 % of its peak (from up to 6.7 %); 0.25 smooths a little more but softens tight
  /// contacts (docs/HAPTICS.md).
  double onset_voxels = 0.1;
  DegradationOptions degradation;
  CoherenceOptions coherence;
  FrictionOptions friction;

  /// δ (m) for a field of voxel `cell_size` (m): onset_depth if given (> 0), else
  /// onset_voxels × cell_size (0 when cell_size is 0).
  double onset_depth_for(double cell_size) const noexcept {
    return onset_depth > 0.0 ? onset_depth : onset_voxels * cell_size;
  }

  /// @throws Error naming the first option out of range.
  void validate() const;
};

}  // namespace khz::contact
