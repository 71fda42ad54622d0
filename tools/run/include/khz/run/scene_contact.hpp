#pragma once
// The contact side of a prepared scene's haptic cycle: the held object against every other
// object it touches, each pair one contact query, the results summed (thesis §4.1, Figure 4.2).

#include <khz/contact/field/deformed_distance_field.hpp>
#include <khz/contact/field/distance_grid.hpp>
#include <khz/contact/query/contact_workspace.hpp>
#include <khz/contact/tree/deformable_point_tree.hpp>
#include <khz/contact/tree/point_tree.hpp>
#include <khz/haptic/cycle/contact_scene.hpp>
#include <khz/reduced/subspace/reduced_integrator.hpp>

#include <Eigen/Geometry>

#include <memory>
#include <variant>
#include <vector>

namespace khz::run {

/// One object as the contact side sees it while a scene runs.
struct ContactBody {
  /// World ← body. The held object's is set by every query(); the others keep theirs.
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  /// The pointshell's tree when the object has that role: a rigid PointTree or a reduced
  /// DeformablePointTree (null when it has no pointshell role).
  std::variant<std::monostate, const contact::PointTree*, const contact::DeformablePointTree*> tree;
  /// The distance field when the object has that role: a rigid grid, or the deformed field's
  /// state, which advance() updates to the object's q.
  std::variant<std::monostate, const contact::DistanceGrid*, contact::DeformedFieldState*> field;
  /// A reduced object's integrator (r coordinates), stepped by advance(); null for rigid ones.
  reduced::ReducedIntegrator* integrator = nullptr;
};

/// The held object (one role: pointshell or distance field) against every other object with the
/// complementary role: one contact::ContactWorkspace per pair. query() places the held object,
/// queries each pair and sums force, torque, their gradients and the statistics (nodes, points
/// in contact and µs add up; the deepest level is the largest; complete only if every pair is);
/// each deformable object collects its reduced contact force over the pairs it is in, and
/// advance() steps it once under the sum (§3.6.1; a deformed field object, §3.12, is then
/// update()d to its new q).
///
/// Gradients add because every pair's are with respect to the same motion: the held object's
/// grasp frame. One virtual call per cycle, one variant dispatch per pair, no allocation.
class SceneContact final : public haptic::ContactScene {
 public:
  /// @param bodies every object of the scene (the trees, fields and integrators must outlive
  ///        this object; the integrators' dimension must be the trees' and fields' r).
  /// @param held index of the held object in `bodies`.
  /// @param grasp_in_body the grasp point G in the held object's body frame (m): body pose =
  ///        grasp pose · translation(−G).
  /// @param options contact options; haptic_object says which role the held object plays.
  /// @throws Error if `held` is out of range or lacks its role, no other object has the
  ///         complementary role, a deformable object has no integrator of its r, or the
  ///         options are invalid.
  SceneContact(std::vector<ContactBody> bodies, int held, const Eigen::Vector3d& grasp_in_body,
               const contact::ContactOptions& options);
  ~SceneContact() override;

  const contact::ContactResult* query(const haptic::Pose& grasp) noexcept override;
  bool advance() noexcept override;

  /// The objects, with the held one at its last queried pose.
  const std::vector<ContactBody>& bodies() const noexcept { return m_bodies; }
  /// Number of pairs queried per cycle.
  int pair_count() const noexcept { return static_cast<int>(m_pairs.size()); }
  /// The last query of pair `pair` (0 ≤ pair < pair_count()).
  const contact::ContactResult& pair_result(int pair) const noexcept;
  /// The objects of pair `pair`: its pointshell's and its field's index in bodies().
  std::pair<int, int> pair_objects(int pair) const noexcept;
  /// Forgets every pair's temporal coherence and level of detail (a jump of the held object).
  void reset() noexcept;
  /// Replaces every pair's options (and resets them). @throws Error as ContactWorkspace.
  void set_options(const contact::ContactOptions& options);

 private:
  struct Pair {
    int pointshell = 0;
    int field = 0;
    std::unique_ptr<contact::ContactWorkspace> workspace;
  };
  bool query_pair(Pair& pair, const Eigen::Vector3d& grasp_point) noexcept;

  std::vector<ContactBody> m_bodies;
  int m_held;
  Eigen::Vector3d m_grasp_in_body;
  std::vector<Pair> m_pairs;
  std::vector<Eigen::VectorXd> m_reduced_forces;  // per body: Σ over its pairs (r, or empty)
  contact::ContactResult m_result;
};

}  // namespace khz::run
