#pragma once
// The stiffness static virtual coupling can render (thesis §4.7).

#include <khz/haptic/export.hpp>

#include <Eigen/Core>

namespace khz::haptic {

/// Contact stiffness ‖J‖₂ (N/m): the 2-norm (largest singular value) of a contact force gradient
/// J = ∂F_C/∂x, the largest force change per unit displacement (§4.7). For multiplane penalty
/// contact, J = −Σ kᵢ nᵢ nᵢᵀ (eq. 4.34) and ‖J‖₂ ≤ k₁ + … + k_ℓ, with equality iff all nᵢ agree.
KHZ_HAPTIC_API double contact_stiffness(const Eigen::Matrix3d& force_by_translation) noexcept;

/// The largest stiffness (N/m) rendered to the device by static virtual coupling of stiffness
/// k_VC against multiplane penalty contact of stiffness ‖J‖₂, in a 3-DOF simulation with
/// continuous time control (§4.7, eq. 4.31; eq. 4.30 with ‖J‖₂ = ℓ k_C):
///   1 / (1/‖J‖₂ + 1/k_VC)  ≤  min(k_VC, ‖J‖₂).
/// So k_VC bounds what the device feels however many points touch: choose it no larger than the
/// device's maximum stable stiffness (CouplingOptions::device_max_stiffness checks this).
/// @param coupling_stiffness k_VC > 0 (N/m).
/// @param contact_stiffness ‖J‖₂ ≥ 0 (N/m; 0 in free space, +∞ for a rigid wall).
KHZ_HAPTIC_API double rendered_stiffness_bound(double coupling_stiffness,
                                               double contact_stiffness) noexcept;

}  // namespace khz::haptic
