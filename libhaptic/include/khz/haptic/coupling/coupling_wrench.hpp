#pragma once
// The static virtual coupling force and torque on the simulation object and their gradients
// (thesis §4.3–§4.4, saturated as §4.9).

#include <khz/haptic/common.hpp>
#include <khz/haptic/export.hpp>

#include <Eigen/Core>

#include <limits>

namespace khz::haptic {

/// The two springs between the manipulandum and the simulation object (§3.1.1, §4.3).
struct CouplingSprings {
  /// k_VC (N/m) of eq. 4.13, > 0.
  double stiffness = 500.0;
  /// k_VC,torque (N·m) of eq. 4.14, > 0: the torque is k_VC,torque sin(θ/2) along the axis,
  /// so its stiffness for small angles is k_VC,torque/2 per radian.
  double torque_stiffness = 1.0;
  /// The plateau F_VC,max (N) of eq. 4.39: the force is linear up to F_VC,max/2; +∞: never
  /// saturates.
  double saturation_force = std::numeric_limits<double>::infinity();
  /// The plateau (N·m) the torque saturates to in the same way (§4.9's extension); +∞: never.
  double saturation_torque = std::numeric_limits<double>::infinity();
};

/// F_VC and T_VC on the simulation object with their nonzero gradients. The gradients are with
/// respect to a small translation Δx (m, world) of the simulation object and a small rotation
/// Δω (rad, world axes, about the grasp point: x_s fixed, q_s ← exp(Δω) q_s), the manipulandum
/// held fixed; ∂F_VC/∂ω = 0 and ∂T_VC/∂x = 0 (eq. 4.17).
struct CouplingWrench {
  /// F_VC (N): k_VC (x_m − x_s) (eq. 4.13), saturated by eq. 4.39.
  Eigen::Vector3d force = Eigen::Vector3d::Zero();
  /// T_VC (N·m): k_VC,torque vector(toPositiveHemisphere(q_m q_s⁻¹)) (eq. 4.14–4.15), saturated
  /// like the force.
  Eigen::Vector3d torque = Eigen::Vector3d::Zero();
  /// ∂F_VC/∂x (N/m): −k_VC I (eq. 4.17), eq. 4.40 where saturated.
  Eigen::Matrix3d force_by_translation = Eigen::Matrix3d::Zero();
  /// ∂T_VC/∂ω (N·m/rad): −½ (k_VC,torque w I + T̃), w = scalar(toPositiveHemisphere(q_m q_s⁻¹))
  /// and T the unsaturated torque (eq. 4.24–4.25 with scalar(q_T) = −k_VC,torque w), times the
  /// saturation's derivative where saturated. Smooth except at a half turn (w = 0), where the
  /// torque's direction flips.
  Eigen::Matrix3d torque_by_rotation = Eigen::Matrix3d::Zero();
  /// k_VC (x_m − x_s) before saturation: §4.9 renders its negative to the device.
  Eigen::Vector3d linear_force = Eigen::Vector3d::Zero();
  /// The torque before saturation.
  Eigen::Vector3d linear_torque = Eigen::Vector3d::Zero();
  bool force_saturated = false;   ///< ‖linear_force‖ > saturation_force/2.
  bool torque_saturated = false;  ///< ‖linear_torque‖ > saturation_torque/2.
};

/// The coupling between the manipulandum and the simulation object, both given by their grasp
/// point (world, m) and orientation (unit quaternions; either may be on either hemisphere).
KHZ_HAPTIC_API CouplingWrench coupling_wrench(const Pose& manipulandum, const Pose& simulation,
                                              const CouplingSprings& springs) noexcept;

}  // namespace khz::haptic
