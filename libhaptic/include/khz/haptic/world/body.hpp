#pragma once
// One object of a World: where it is, what it touches with, how it deforms and, if it is free,
// how it moves.

#include <khz/contact/field/deformed_distance_field.hpp>
#include <khz/contact/field/distance_grid.hpp>
#include <khz/contact/field/implicit_shapes.hpp>
#include <khz/contact/tree/deformable_point_tree.hpp>
#include <khz/contact/tree/point_tree.hpp>
#include <khz/haptic/world/free_body_motion.hpp>
#include <khz/reduced/subspace/reduced_integrator.hpp>

#include <Eigen/Geometry>

#include <optional>
#include <string>
#include <variant>

namespace khz::haptic {

/// A body's pointshell role (thesis §3.8–§3.9): a rigid PointTree, or a reduced body's
/// DeformablePointTree (its points follow the body's q), or none.
using BodyPointshell =
    std::variant<std::monostate, const contact::PointTree*, const contact::DeformablePointTree*>;

/// A body's distance-field role (§3.11–§3.12): a rigid DistanceGrid or analytic shape (§3.11.1:
/// an ImplicitShape or an ImplicitUnion of them), or a reduced body's DeformedFieldState (which
/// the World update()s to the body's q after each step), or none.
using BodyField =
    std::variant<std::monostate, const contact::DistanceGrid*, const contact::ImplicitShape*,
                 const contact::ImplicitUnion*, contact::DeformedFieldState*>;

/// What makes a body dynamic (issue 20): neither held nor fixed, it moves under gravity and the
/// contacts it is in (FreeBodyMotion), and a hand may grasp it (World::grasp()).
struct BodyDynamics {
  /// Mass, centre of mass and inertia in the body frame: reduced::mass_properties() gives them
  /// for a closed mesh and a density.
  RigidInertia inertia;
  /// At the start, of the centre of mass (m/s, world).
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();
  /// At the start (rad/s, world).
  Eigen::Vector3d angular_velocity = Eigen::Vector3d::Zero();
};

/// One body of a World. Everything it points to is borrowed: the trees, fields and integrator
/// must outlive the World, and nothing else may use them while its cycles run.
///
/// Units and frames: metres and the body's own frame for the trees and fields (a mesh read from a
/// file is taken to be in metres: scale it first if it is not); `pose` places the body frame in
/// the world. A body needs at least one role to be in contact; two bodies touch when one's
/// pointshell meets the other's field.
struct Body {
  /// For messages and logs ("body 2" when empty).
  std::string name;
  /// World ← body, a rigid transform. A fixed body stays here; a held body starts here and is
  /// then placed by its hand's coupling every cycle.
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  BodyPointshell pointshell;
  BodyField field;
  /// The integrator of a reduced body (its r must be that of its deformable tree and deformed
  /// field, whichever it has); null for a rigid body. The World steps it once per cycle under
  /// the sum of its reduced contact forces over every pair it is in.
  reduced::ReducedIntegrator* integrator = nullptr;
  /// Set for a dynamic body (rigid only: no integrator). A hand may not hold it from the start;
  /// it may grasp it (World::grasp()). Unset: the body is fixed, or held by a hand.
  std::optional<BodyDynamics> dynamics;
};

}  // namespace khz::haptic
