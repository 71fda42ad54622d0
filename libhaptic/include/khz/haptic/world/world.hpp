#pragma once
// The multi-body contact runtime: bodies, the hands that hold some of them, the contact pairs
// between them, and the haptic cycle of thesis Figure 4.2 run for every hand at once.

#include <khz/contact/query/contact_options.hpp>
#include <khz/contact/query/contact_result.hpp>
#include <khz/haptic/coupling/virtual_coupling.hpp>
#include <khz/haptic/export.hpp>
#include <khz/haptic/world/body.hpp>
#include <khz/haptic/world/cycle_metrics.hpp>
#include <khz/haptic/world/cycle_record.hpp>
#include <khz/haptic/world/dynamics_options.hpp>
#include <khz/haptic/world/free_body_motion.hpp>
#include <khz/haptic/world/hand.hpp>

#include <functional>
#include <memory>
#include <span>
#include <vector>

namespace khz::haptic {

/// Whether bodies a and b (indices, a < b) may touch: false leaves the pair out of every query.
/// Called only while the World is built.
using PairFilter = std::function<bool(int body_a, int body_b)>;

/// One queried pair: body `pointshell`'s pointshell against body `field`'s distance field, the
/// wrench taken on `body` (one of the two, a moving one). A pair of two moving bodies (held or
/// dynamic) is queried twice, once for each.
struct WorldPair {
  int pointshell = 0;  ///< Body index.
  int field = 0;       ///< Body index.
  /// The body whose wrench this query gives: a held body (its hand feels it), a free dynamic
  /// body (it moves under it) or a dynamic body a hand grasped (that hand feels it).
  int body = 0;
  /// Whether this is its pair's first query (false for the second query of a pair of two moving
  /// bodies): pictures draw each pair once. The reduced forces of a pair step its deformable
  /// bodies from the first of its queries that ran in the cycle.
  bool applies_reduced_forces = true;
};

/// N bodies (rigid or reduced, each with a pointshell and/or a distance field; fixed, held or
/// dynamic), any number of hands (each a device, its safety layer and its virtual coupling holding
/// one body), and the pairs between them. Every cycle:
///
///   1. each hand's device is read (SafeDevice::read()) into its manipulandum pose; a hand with a
///      Hand::grasp_button grasps when it is pressed and releases when it is let go (grasp());
///   2. each held body is placed at its coupling's simulation pose, and each grasped body with it;
///   3. every pair is queried (one contact::ContactWorkspace each, allocated here), and each
///      hand's wrench is the sum over its pairs, and those of the bodies it grasped, plus their
///      weight (contact::ContactWrench::accumulate(): all about the hand's grasp point and for the
///      motion of its body); each free dynamic body's wrench is the sum over its pairs, about its
///      centre of mass;
///   4. each hand's coupling steps under its manipulandum and wrench (§4.1–§4.10);
///   5. each free dynamic body that is awake steps under gravity and its wrench
///      (FreeBodyMotion, DynamicsOptions), and sleeps once it has been still for a while;
///   6. each reduced body is stepped once under the sum of its reduced contact forces over all
///      its pairs (§3.6.1), and a deformed field is then update()d to its new q (§3.12);
///   7. each device is written the coupling's rendered wrench (zero when anything in its chain
///      failed), the hand's CycleMetrics records the cycle, and its watchdog closes the cycle.
///
/// Pairs: for every moving body m (held or dynamic) and every other body b, one pair when one's
/// pointshell can meet the other's field (m touches with its Hand::role, or else
/// ContactOptions::haptic_object, when both ways are possible), unless the filter says no. A pair
/// of two moving bodies is queried once for each (each feels its own wrench, with its own
/// gradients); fixed bodies do not touch one another. A pair inside one hand's grasp (its body
/// and a body it grasped, or two it grasped) is not queried. A hand whose device read fails
/// renders zero and its body stays where it was, still touching the others; a query that refuses
/// its input (e.g. a non-finite pose) counts for nothing that cycle and makes its hand render
/// zero (or its dynamic body move under gravity alone).
///
/// cycle() allocates nothing, takes no lock and throws nothing; the constructor and the setters
/// may. Not copyable or movable (the parts refer to one another); one thread runs the cycles.
class KHZ_HAPTIC_API World {
 public:
  /// @param bodies the bodies (what they point to is borrowed, see Body).
  /// @param hands at most one per body, each with a device.
  /// @param options the contact settings of every pair (haptic_object only says which role a
  ///        held body prefers when its hand does not say, see above).
  /// @param filter which body pairs may touch (all when empty).
  /// @throws Error naming the body or hand: a hand's body index out of range or held twice, a
  ///         hand without a device, a held body with neither role, a held body that is dynamic
  ///         (grasp it instead), a dynamic body that is reduced or whose inertia fails
  ///         RigidInertia::validate(), a reduced body without an integrator of its tree's or
  ///         field's r, invalid coupling or contact options, friction with the default stick
  ///         distance against a body whose field is analytic (no voxel to choose it from), or
  ///         no pair at all.
  World(std::vector<Body> bodies, std::vector<Hand> hands, const contact::ContactOptions& options,
        PairFilter filter = {});
  ~World();
  World(const World&) = delete;
  World& operator=(const World&) = delete;

  /// One cycle of every hand starting at `now` with deadline `deadline` (s, the loop's clock);
  /// `clock` is read again at the end for each device's watchdog (a callable returning seconds
  /// on the same clock). Returns one record per hand, in the hands' order.
  template <typename Clock>
  std::span<const CycleRecord> cycle(double now, double deadline, Clock&& clock) noexcept {
    begin_cycle(deadline);
    step(now);
    end_cycle(clock());
    return records();
  }

  /// The last cycle's records, one per hand.
  std::span<const CycleRecord> records() const noexcept;
  /// The bodies, each held one at its last placement.
  std::span<const Body> bodies() const noexcept;
  int hand_count() const noexcept;
  const Hand& hand(int index) const noexcept;
  /// The coupling of hand `index` (its simulation pose is where its body is queried).
  VirtualCoupling& coupling(int index) noexcept;
  const VirtualCoupling& coupling(int index) const noexcept;
  /// The pairs queried every cycle.
  std::span<const WorldPair> pairs() const noexcept;
  /// The last query of pair `index`.
  const contact::ContactResult& pair_result(int index) const noexcept;
  /// The last cycle's reduced contact force on body `index` (r entries; empty for a rigid body).
  const Eigen::VectorXd& reduced_force(int index) const noexcept;
  /// Hand `index`'s contact wrench of the last cycle or probe(): the sum over its pairs, about
  /// its grasp point (force N, torque N·m, gradients per m and per rad).
  const contact::ContactWrench& wrench(int index) const noexcept;
  /// Hand `index`'s smoothness, jitter, residual, penetration and energy figures over the cycles
  /// since construction or reset_metrics() (each cycle() records into its hand's CycleMetrics;
  /// probe() does not).
  CycleMetricsSummary metrics(int index) const noexcept;
  /// Forgets every hand's metrics (the passivity observers restart at 0).
  void reset_metrics() noexcept;

  /// Contact as it would be with every held body at its hand's grasp frame in `grasps` (one
  /// pose per hand, world frame) and every other body as it is (reduced ones at their current
  /// q): places the held bodies there and queries every pair, stepping nothing and touching no
  /// device or coupling. Read the result with wrench() and pair_result(). For replaying recorded
  /// states (e.g. the speed-against-error sweep of `khz report`); the pairs' temporal coherence
  /// and level of detail carry over between probes as between cycles. Allocates nothing.
  /// @return false if `grasps` has the wrong size or a query refused its input (that hand's
  ///         wrench then counts only the pairs that answered).
  bool probe(std::span<const Pose> grasps) noexcept;

  /// Gives the dynamic bodies new settings (the defaults until then).
  /// @throws Error as DynamicsOptions::validate().
  void set_dynamics(const DynamicsOptions& options);
  const DynamicsOptions& dynamics() const noexcept;
  /// The motion of dynamic body `index` (its pose, velocities, energy and momentum), or null
  /// when the body is not dynamic. While a hand grasps it, it is where the hand put it, moving
  /// as the hand's grasp frame moved over the last cycle.
  const FreeBodyMotion* motion(int index) const noexcept;
  /// Whether dynamic body `index` sleeps (false for any other body).
  bool asleep(int index) const noexcept;
  /// Dynamic body `index`'s contact wrench of the last cycle about its centre of mass (zero
  /// while a hand grasps it, or for a body that is not dynamic).
  const contact::ContactWrench& body_wrench(int index) const noexcept;
  /// Hand `hand` grasps the free dynamic body its body touches hardest (the largest contact
  /// force in the last cycle or probe()): from now on that body rides with the hand's body at
  /// their present relative pose, its contacts and weight are part of the hand's wrench, and
  /// the pair between the two is not queried.
  /// @return the grasped body's index; −1 if the hand touches no free dynamic body, or `hand`
  ///         is out of range. Allocates nothing.
  int grasp(int hand) noexcept;
  /// Hands every body hand `hand` grasped back to dynamics, moving as the hand's body moved over
  /// the last cycle. @return how many it released (0 for a hand out of range).
  int release(int hand) noexcept;
  /// The hand that holds or grasped body `index`, or −1.
  int hand_of(int index) const noexcept;
  /// Puts free dynamic body `index` at `pose` (world ← body), at rest and awake: for replaying
  /// recorded states with probe(), which then queries its pairs too. A jump like any other: its
  /// pairs' friction anchors, coherence and level of detail carry on (reset_contact() forgets
  /// them). Allocates nothing.
  /// @return false (and nothing changes) if the body is not dynamic, a hand grasps it, or `pose`
  ///         is not finite.
  bool place_free_body(int index, const Eigen::Isometry3d& pose) noexcept;

  /// Forgets every pair's temporal coherence and level of detail (after a jump of a body).
  void reset_contact() noexcept;
  /// Replaces every pair's contact options (and resets them). The pairs stay as built.
  /// @throws Error as contact::ContactWorkspace, or as the constructor for friction's default
  ///         stick distance against an analytic field.
  void set_contact_options(const contact::ContactOptions& options);
  /// The contact options last given (constructor or set_contact_options()), before each pair
  /// gets its hand's role as the haptic object.
  const contact::ContactOptions& contact_options() const noexcept;
  /// Gives the pairs between bodies a and b (in either role, and for either hand) their own
  /// friction in place of contact_options().friction, now and after set_contact_options(); and
  /// resets them.
  /// @throws Error naming the bodies if a or b is out of range, they are the same, no pair joins
  ///         them, `friction` is invalid (contact::ContactOptions::validate()), or it leaves
  ///         the stick distance to the voxel of an analytic field, which has none.
  void set_pair_friction(int body_a, int body_b, const contact::FrictionOptions& friction);
  /// The friction pair `index` is queried with.
  const contact::FrictionOptions& pair_friction(int index) const noexcept;
  /// What friction did at point `point` of pair `index`'s pointshell in its last query
  /// (contact::ContactWorkspace::friction_state()): for pictures of stuck and sliding points.
  contact::FrictionState friction_state(int index, Eigen::Index point) const noexcept;

 private:
  void begin_cycle(double deadline) noexcept;
  void step(double now) noexcept;
  void end_cycle(double now) noexcept;
  /// Steps every free dynamic body that is awake, and puts it to sleep once it is still.
  void step_dynamic_bodies() noexcept;
  /// Places hand h's body at grasp frame `grasp`, and the bodies it grasped with it.
  void place_held_body(std::size_t hand, const Pose& grasp) noexcept;
  /// Queries every pair into its hand's wrench and each body's reduced force; false if any
  /// query refused (that hand's contact_ok is then false).
  bool query_pairs() noexcept;

  struct Data;
  std::unique_ptr<Data> m_data;
};

}  // namespace khz::haptic
