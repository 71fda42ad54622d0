#pragma once
// The contact half of a haptic cycle (thesis §4.1, Figure 4.2): one held object against one
// other, queried at the simulation pose, with the deformable objects' time steps.

#include <khz/contact/query/contact_query.hpp>
#include <khz/haptic/common.hpp>
#include <khz/reduced/subspace/reduced_integrator.hpp>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <string>
#include <type_traits>

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

/// A pointshell object (a PointTree, or a DeformablePointTree with its ReducedIntegrator) against a
/// distance-field object of type Field (a rigid field, or a deformable one such as a
/// DeformedFieldState with its ReducedIntegrator), one of them held.
///
/// The held object is placed by its grasp frame: body pose = grasp pose · translation(−G), with
/// G the grasp point in the held object's body coordinates (orientations coincide). The other
/// object stays at `fixed_pose`. A deformable pointshell's q comes from its integrator. advance()
/// steps each deformable object under its share of the contact (§3.6.1, §3.12: the pointshell
/// under ContactResult::pointshell_reduced_force, the field object under field_reduced_force,
/// which the field is then update()d to).
template <typename Tree, contact::DistanceField Field>
class PointshellFieldScene final : public ContactScene {
  static constexpr bool deformable_field = contact::DeformableDistanceField<Field>;
  using FieldReference = std::conditional_t<deformable_field, Field&, const Field&>;

 public:
  /// @param integrator the deformable pointshell's integrator (DeformablePointTree only; r
  ///        coordinates), nullptr for a rigid pointshell.
  /// @param field_integrator a deformable field object's integrator (its dimension() coordinates;
  ///        the field must offer update(q)), nullptr for a rigid one.
  /// @throws Error as ContactWorkspace, or if a deformable object comes without an integrator of
  ///         its dimension.
  PointshellFieldScene(const Tree& tree, FieldReference field,
                       const contact::ContactOptions& options, const Eigen::Vector3d& grasp_in_body,
                       const Eigen::Isometry3d& fixed_pose,
                       reduced::ReducedIntegrator* integrator = nullptr,
                       reduced::ReducedIntegrator* field_integrator = nullptr)
      : m_tree(tree),
        m_field(field),
        m_workspace(tree, options, field_dimension(field)),
        m_grasp_in_body(grasp_in_body),
        m_fixed(fixed_pose),
        m_integrator(integrator),
        m_field_integrator(field_integrator) {
    if constexpr (std::is_same_v<Tree, contact::DeformablePointTree>) {
      if (integrator == nullptr || integrator->dimension() != tree.dimension()) {
        throw Error("PointshellFieldScene: a deformable pointshell needs its integrator (r = " +
                    std::to_string(tree.dimension()) + ")");
      }
    }
    if constexpr (deformable_field) {
      if (field_integrator == nullptr || field_integrator->dimension() != field.dimension()) {
        throw Error("PointshellFieldScene: a deformable field object needs its integrator (r = " +
                    std::to_string(field.dimension()) + ")");
      }
    }
  }

  const contact::ContactResult* query(const Pose& grasp) noexcept override {
    const Eigen::Isometry3d held = held_body_pose(grasp, m_grasp_in_body);
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
    bool ok = true;
    if (m_integrator != nullptr) {
      ok = m_integrator->step(m_workspace.result().pointshell_reduced_force).status !=
           reduced::ReducedStepStatus::failed;
    }
    if constexpr (deformable_field) {
      ok = m_field_integrator->step(m_workspace.result().field_reduced_force).status !=
               reduced::ReducedStepStatus::failed &&
           ok;
      ok = m_field.update(m_field_integrator->coordinates()) && ok;
    }
    return ok;
  }

  contact::ContactWorkspace& workspace() noexcept { return m_workspace; }

 private:
  const Tree& m_tree;
  static Eigen::Index field_dimension(const Field& field) noexcept {
    if constexpr (deformable_field) {
      return field.dimension();
    } else {
      return 0;
    }
  }

  FieldReference m_field;
  contact::ContactWorkspace m_workspace;
  Eigen::Vector3d m_grasp_in_body;
  Eigen::Isometry3d m_fixed;
  reduced::ReducedIntegrator* m_integrator;
  reduced::ReducedIntegrator* m_field_integrator;
};

/// Deduces the scene's types from its tree and field (a deformable field is taken by non-const
/// reference: the scene update()s it).
template <typename Tree, typename Field, typename... Rest>
PointshellFieldScene(const Tree&, Field&, Rest&&...)
    -> PointshellFieldScene<Tree, std::remove_const_t<Field>>;

}  // namespace khz::haptic
