#pragma once
// The time-critical contact query (thesis §3.10): a nested point tree, rigid or reduced
// deformable, traversed level by level against a distance-field object — a grid, an analytic
// shape, a deformed field or any type satisfying DistanceField — with penalty forces (§3.5),
// force gradients (§4.2), graceful degradation (§3.10.3) and temporal coherence (§3.10.2).

#include <khz/contact/field/distance_field.hpp>
#include <khz/contact/query/contact_frames.hpp>
#include <khz/contact/query/contact_options.hpp>
#include <khz/contact/query/contact_result.hpp>
#include <khz/contact/query/contact_workspace.hpp>
#include <khz/contact/query/detail/tree_traversal.hpp>
#include <khz/contact/tree/deformable_point_tree.hpp>
#include <khz/contact/tree/point_tree.hpp>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace khz::contact {

/// One query of a rigid pointshell against `field`; the result is in workspace.result().
///
/// Each point p of the tree is moved to the world (x = pose_P p) and into the field's frame
/// (X = pose_F⁻¹ x); a point with d = field(X) < 0 is in contact and pushes the field object
/// with f = w k_C d N (N its inward normal in the world, eq. 3.1; the pointshell gets −f). Nodes
/// whose sphere cannot reach the field (d > radius) are culled with their subtree.
///
/// Cost (bench_contact_query): about 1 distance lookup and 20 flops per traversed node.
/// Allocates nothing, throws nothing, takes no lock.
/// @returns false, with a zero result, if the workspace was made for another tree, a pose or
///          the grasp point is not finite, or friction is on with its default stick distance
///          against a field without cells (FrictionOptions::stick_distance).
template <DistanceField Field>
bool query_contact(const PointTree& tree, const Field& field, const ContactFrames& frames,
                   ContactWorkspace& workspace) noexcept {
  return detail::TraversalAccess::run(detail::RigidPoints(tree), field, frames, workspace);
}

/// One query of a reduced deformable pointshell in configuration q (r entries) against
/// `field`: points at p_s = P_s + U_s q (eq. 3.6), bounding radii R_i(q) (eq. 3.12), and
/// normals (eq. 3.8) only for points in contact, so a culled subtree costs nothing; adds
/// ContactResult::pointshell_reduced_force = Σ U_sᵀ f_s for the pointshell's integrator. About
/// 4r more flops per traversed node than the rigid query.
/// @returns false, with a zero result, as the rigid query does, or if q does not have r entries
///          or is not finite.
template <DistanceField Field>
bool query_contact(const DeformablePointTree& tree, const Eigen::Ref<const Eigen::VectorXd>& q,
                   const Field& field, const ContactFrames& frames,
                   ContactWorkspace& workspace) noexcept {
  const double* abs_q = detail::TraversalAccess::absolute_q(workspace, q);
  if (abs_q == nullptr) {
    detail::TraversalAccess::fail(workspace);
    return false;
  }
  return detail::TraversalAccess::run(detail::DeformablePoints(tree, q, abs_q), field, frames,
                                      workspace);
}

}  // namespace khz::contact
