#pragma once
// What one contact query returns (thesis §3.5, §3.6.1, §3.12, §4.1–§4.2).

#include <khz/contact/export.hpp>
#include <khz/contact/query/contact_wrench.hpp>

#include <Eigen/Core>

namespace khz::contact {

/// Everything one query returns: the wrench on the haptic object (in the world frame, about the
/// grasp point; see ContactWrench) and the reactions on deformable objects. With ℓ the
/// (weighted) count of points in contact, everything is scaled by L/ℓ once ℓ > L (§3.5); ℓ is
/// held fixed in the gradients.
struct KHZ_CONTACT_API ContactResult : ContactWrench {
  /// Σ U_sᵀ f_s over the points in contact of a deformable pointshell, f_s the force on the
  /// point in the pointshell's body frame (§3.6.1): the external reduced force for its
  /// integrator (r_pointshell entries; empty for a rigid pointshell).
  Eigen::VectorXd pointshell_reduced_force;
  /// The reaction on a deformable distance-field object, projected on the modes of the proxy
  /// nearest to each contact (§3.12; empty for a rigid field).
  Eigen::VectorXd field_reduced_force;
};

}  // namespace khz::contact
