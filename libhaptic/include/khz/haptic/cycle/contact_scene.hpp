#pragma once
// The contact half of a haptic cycle (thesis §4.1, Figure 4.2): one held object against one
// other, queried at the simulation pose, with the deformable objects' time steps.

#include <khz/contact/query/contact_query.hpp>
#include <khz/haptic/common.hpp>
#include <khz/reduced/subspace/reduced_newmark.hpp>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace khz::haptic {

/// What HapticCycle needs from the contact side, behind one virtual call per cycle (never per
/// point). Both members run on the haptic thread: noexcept, allocation-free.
class ContactScene {
 public:
  virtual ~ContactScene() = default;
  /// The contact result for the held object's grasp frame at `grasp` (simulation world): force
  /// and torque on the held object about its grasp point, and their gradients; nullptr if the
  /// query refused its input.
  virtual const contact::ContactResult* query(const Pose& grasp) noexcept = 0;
  /// Advances every deformable object one time step under the last query's reduced forces
  /// (§3.6.1: at the end of the cycle); false if an integrator failed (its state is kept).
  virtual bool advance() noexcept = 0;
};

/// A pointshell object (a PointTree, or a DeformablePointTree with its ReducedNewmark) against a
/// distance-field object of type Field, one of them held.
///
/// The held object is placed by its grasp frame: body pose = grasp pose · translation(−G), with
/// G the grasp point in the held object's body coordinates (orientations coincide). The other
/// object stays at `fixed_pose`. A deformable pointshell's q comes from its integrator, and
/// advance() steps it under ContactResult::pointshell_reduced_force (a deformable field is the
/// caller's to update: Field is then a DeformedFieldState it owns).
template <typename Tree, contact::DistanceField Field>
class PointshellFieldScene final : public ContactScene {
 public:
  /// @param integrator the deformable pointshell's integrator (DeformablePointTree only; r
  ///        coordinates), nullptr for a rigid pointshell.
  /// @param field_dimension r of a deformable field object, else 0.
  /// @throws Error as ContactWorkspace, or if a deformable pointshell comes without an
  ///         integrator of its dimension.
  PointshellFieldScene(const Tree& tree, const Field& field, const contact::ContactOptions& options,
                       const Eigen::Vector3d& grasp_in_body, const Eigen::Isometry3d& fixed_pose,
                       reduced::ReducedNewmark* integrator = nullptr,
                       Eigen::Index field_dimension = 0)
      : m_tree(tree),
        m_field(field),
        m_workspace(tree, options, field_dimension),
        m_grasp_in_body(grasp_in_body),
        m_fixed(fixed_pose),
        m_integrator(integrator) {
    if constexpr (std::is_same_v<Tree, contact::DeformablePointTree>) {
      if (integrator == nullptr || integrator->dimension() != tree.dimension()) {
        throw Error("PointshellFieldScene: a deformable pointshell needs its integrator (r = " +
                    std::to_string(tree.dimension()) + ")");
      }
    }
  }

  const contact::ContactResult* query(const Pose& grasp) noexcept override {
    Eigen::Isometry3d held = Eigen::Isometry3d::Identity();
    held.linear() = grasp.orientation.normalized().toRotationMatrix();
    held.translation() = grasp.position - held.linear() * m_grasp_in_body;
    contact::ContactFrames frames;
    frames.grasp_point = grasp.position;
    const bool pointshell_held =
        m_workspace.options().haptic_object == contact::HapticObject::pointshell;
    frames.pointshell = pointshell_held ? held : m_fixed;
    frames.field = pointshell_held ? m_fixed : held;
    bool ok;
    if constexpr (std::is_same_v<Tree, contact::DeformablePointTree>) {
      ok =
          contact::query_contact(m_tree, m_integrator->coordinates(), m_field, frames, m_workspace);
    } else {
      ok = contact::query_contact(m_tree, m_field, frames, m_workspace);
    }
    return ok ? &m_workspace.result() : nullptr;
  }

  bool advance() noexcept override {
    if (m_integrator == nullptr) return true;
    return m_integrator->step(m_workspace.result().pointshell_reduced_force).status !=
           reduced::ReducedStepStatus::failed;
  }

  contact::ContactWorkspace& workspace() noexcept { return m_workspace; }

 private:
  const Tree& m_tree;
  const Field& m_field;
  contact::ContactWorkspace m_workspace;
  Eigen::Vector3d m_grasp_in_body;
  Eigen::Isometry3d m_fixed;
  reduced::ReducedNewmark* m_integrator;
};

}  // namespace khz::haptic
