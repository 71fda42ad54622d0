#pragma once
// The per-pair state of the contact query: traversal lists, the per-cycle distance cache,
// temporal-coherence skips and the warm level, allocated once so a query allocates nothing.

#include <khz/contact/common.hpp>
#include <khz/contact/export.hpp>
#include <khz/contact/query/contact_options.hpp>
#include <khz/contact/query/contact_result.hpp>
#include <khz/contact/query/detail/point_friction.hpp>
#include <khz/contact/tree/deformable_point_tree.hpp>
#include <khz/contact/tree/point_tree.hpp>

#include <Eigen/Core>

#include <cstdint>
#include <span>
#include <vector>

namespace khz::contact {

namespace detail {
struct TraversalAccess;
}

/// Everything one pointshell–field pair keeps from query to query. Create one per pair (and
/// per thread); it belongs to the tree it was made for, which must outlive it. Memory: about
/// 4 bytes per node and 12 per point, and 32 more per point with friction on.
class KHZ_CONTACT_API ContactWorkspace {
 public:
  /// For a rigid pointshell.
  /// @param field_dimension r of a deformable distance-field object (sizes
  ///        ContactResult::field_reduced_force), 0 for a rigid field.
  /// @throws Error if the options fail validate() or field_dimension < 0.
  ContactWorkspace(const PointTree& tree, const ContactOptions& options,
                   Eigen::Index field_dimension = 0);
  /// For a deformable pointshell (sizes ContactResult::pointshell_reduced_force; temporal
  /// coherence uses the tree's displacement_bound()).
  ContactWorkspace(const DeformablePointTree& tree, const ContactOptions& options,
                   Eigen::Index field_dimension = 0);

  const ContactOptions& options() const noexcept { return m_options; }
  /// Replaces the options (and reset()s).
  /// @throws Error if they fail validate(); the workspace is unchanged then.
  void set_options(const ContactOptions& options);

  /// Optional per-point weights (§3.5, e.g. the surface area each point stands for, in units of
  /// the mean): a point in contact adds w_s·k_C·d·N and counts w_s towards ℓ. Indexed like the
  /// tree's points (PointTree::pointshell() order); empty restores weight 1.
  /// @throws Error if the size is not the tree's point count or a weight is not finite and > 0.
  void set_area_weights(std::vector<double> weights);

  /// What friction did at point `point` (PointTree::pointshell() order) in the last query;
  /// none for an index out of range.
  FrictionState friction_state(Eigen::Index point) const noexcept;

  /// Forgets temporal coherence, the warm level, the contact floor, the measured cost per node
  /// and every friction anchor: call it when the objects jump (a teleport, a new scene), though a
  /// query also notices motion beyond the declared bounds itself.
  void reset() noexcept;

  /// The last query's result.
  const ContactResult& result() const noexcept { return m_result; }

 private:
  friend struct detail::TraversalAccess;

  ContactWorkspace(const PointTree& tree, const ContactOptions& options,
                   Eigen::Index pointshell_dimension, Eigen::Index field_dimension);

  /// Starts a query's temporal coherence: advances the cycle, measures the relative motion since
  /// the previous query (pointshell body → field body: `rotation`, `translation`; q of a
  /// deformable pointshell or nullptr) and drops every skip if it exceeds the declared bounds.
  /// Returns whether it dropped them.
  /// `field_q` and `field_bound`: a deformable field object's q and displacement bound (m per
  /// unit q), or nullptr and 0.
  bool begin_coherence(const Eigen::Matrix3d& rotation, const Eigen::Vector3d& translation,
                       const double* q, const double* field_q, double field_bound) noexcept;
  /// The query after which a node culled with gap `gap` (m, > 0) must be looked at again.
  std::uint32_t coherent_skip_until(double gap) const noexcept;
  /// time_budget mode: whether `units` cost units take at most `budget` seconds at the typical
  /// cost per unit, which follows the measured one by at most 1/32 per query either way (so a
  /// stall moves it little, a slower machine in a few hundred queries); true before any
  /// measurement.
  bool fits_at_typical_speed(double units, double budget) const noexcept {
    return units * m_typical_seconds_per_unit <= budget;
  }
  /// After a query: keeps the level of detail, whether it was in contact (then its deepest level
  /// is the next query's floor) and the typical cost per unit.
  void end_degradation(int deepest_level, bool in_contact, double seconds,
                       double cost_units) noexcept;
  /// Starts a query's friction: advances the count the anchors are stamped with.
  void begin_friction() noexcept;
  /// Whether point s's anchor (of a point first appearing on `level`) still holds: it was in
  /// contact in a query since which no query has rendered its level.
  bool anchor_holds(Eigen::Index s, int level) const noexcept {
    const std::uint32_t stamp = m_anchors[static_cast<std::size_t>(s)].query;
    return stamp != 0 && stamp >= m_level_rendered[static_cast<std::size_t>(level)];
  }
  /// Levels [first, end) were rendered by this query: their points not found in contact lose
  /// their anchors.
  void mark_rendered(int first, int end) noexcept {
    for (int level = first; level < end; ++level) {
      m_level_rendered[static_cast<std::size_t>(level)] = m_friction_query;
    }
  }
  /// Sizes the anchors for the options (none when friction is off).
  void size_friction();

  ContactOptions m_options;
  ContactResult m_result;
  const void* m_tree_identity;  // the tree this workspace was made for
  Eigen::Index m_nodes;
  Eigen::Index m_points;
  Eigen::Index m_pointshell_dimension;
  Eigen::Index m_field_dimension;

  std::vector<double> m_area_weights;       // per point; empty = 1
  std::vector<double> m_point_distance;     // per point: d of this query's first visit
  std::vector<std::int32_t> m_current;      // nodes of the level being traversed
  std::vector<std::int32_t> m_next;         // nodes queued for the next level
  Eigen::VectorXd m_abs_q;                  // |q| of a deformable pointshell, per query
  Eigen::VectorXd m_contact_reduced_force;  // scratch: the unscaled Σ U_sᵀ f_s
  // time_budget: the unscaled reduced forces of the levels before one the budget may cut.
  Eigen::VectorXd m_kept_contact_reduced_force;
  Eigen::VectorXd m_kept_field_reduced_force;

  // Temporal coherence.
  std::vector<std::uint32_t> m_skip_until;  // per node: skip while m_cycle < this
  std::uint32_t m_cycle = 0;
  bool m_have_previous = false;
  Eigen::Matrix3d m_previous_rotation;   // pointshell body → field body
  Eigen::Vector3d m_previous_reference;  // reference point in the field frame
  Eigen::VectorXd m_previous_q;
  Eigen::VectorXd m_previous_field_q;
  Eigen::Vector3d m_reference_point;  // pointshell body frame: rest bounding-box centre
  double m_rest_reach = 0.0;          // max_s ‖P_s − reference point‖ (m)
  double m_modes_norm = 0.0;          // DeformablePointTree::displacement_bound() (m per unit q)
  double m_motion_per_query = 0.0;    // bound on any point's motion per query (m)

  // Graceful degradation.
  int m_warm_level = -1;
  int m_contact_floor = -1;  // the previous query's deepest level, if it was in contact
  double m_typical_seconds_per_unit = 0.0;  // time_budget: rate-limited cost per unit (0: none yet)

  // Friction.
  std::vector<detail::FrictionAnchor> m_anchors;  // per point; empty when friction is off
  std::vector<std::uint32_t> m_level_rendered;    // per level: the last query that completed it
  std::uint32_t m_friction_query = 0;             // queries so far (the anchors' stamps)
  double m_last_normal_load = 0.0;  // Σ|f_n| of the last query (N), for the anchors' stretch
};

}  // namespace khz::contact
