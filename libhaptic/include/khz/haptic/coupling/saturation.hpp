#pragma once
// Virtual coupling saturation (thesis §4.9, eq. 4.39–4.40): linear up to half the plateau, then
// an exponential approach to the plateau with a continuous derivative at the joint.

#include <khz/haptic/export.hpp>

#include <Eigen/Core>

namespace khz::haptic {

/// f of eq. 4.39 in terms of the linear spring's magnitude m = k·r:
///   m                          if m ≤ P/2,
///   P (1 − ½ exp(1 − 2m/P))    otherwise,
/// which is eq. 4.39's F_VC,max (1 − ½ exp(2k_VC (r_lin − r)/F_VC,max)) with r_lin = P/(2k_VC).
/// @param magnitude m ≥ 0 (N for a force, N·m for a torque).
/// @param plateau P > 0, or +∞ for no saturation.
KHZ_HAPTIC_API double saturation_profile(double magnitude, double plateau) noexcept;

/// A saturated vector and its derivative with respect to the linear one.
struct SaturatedVector {
  Eigen::Vector3d value = Eigen::Vector3d::Zero();
  /// ∂value/∂linear: I in the linear part; beyond it, with m = ‖v‖, e = v/m, f = f(m):
  /// (f/m) I + (f′ − f/m) e eᵀ — chained with ∂v/∂x = −k_VC I this is eq. 4.40.
  Eigen::Matrix3d jacobian = Eigen::Matrix3d::Identity();
  /// Whether ‖v‖ was beyond the linear part (> P/2).
  bool saturated = false;
};

/// The vector v of a linear spring (k_VC (x_m − x_s), or the unsaturated coupling torque)
/// shortened to saturation_profile(‖v‖, plateau) along its own direction.
KHZ_HAPTIC_API SaturatedVector saturate(const Eigen::Vector3d& linear, double plateau) noexcept;

}  // namespace khz::haptic
