#include <khz/contact/query/detail/cross_matrix.hpp>
#include <khz/haptic/coupling/coupling_wrench.hpp>
#include <khz/haptic/coupling/rotation_vector.hpp>
#include <khz/haptic/coupling/saturation.hpp>

namespace khz::haptic {
using contact::detail::cross_matrix;

CouplingWrench coupling_wrench(const Pose& manipulandum, const Pose& simulation,
                               const CouplingSprings& springs) noexcept {
  CouplingWrench wrench;

  // Eq. 4.13; ∂/∂x_s of k_VC (x_m − x_s) is −k_VC I (eq. 4.17), chained through eq. 4.39.
  wrench.linear_force = springs.stiffness * (manipulandum.position - simulation.position);
  const SaturatedVector force = saturate(wrench.linear_force, springs.saturation_force);
  wrench.force = force.value;
  wrench.force_by_translation = -springs.stiffness * force.jacobian;
  wrench.force_saturated = force.saturated;

  // Eq. 4.14–4.15. Under q_s ← exp(Δω) q_s ≈ (1 + ½Δω̂) q_s, p = q_m q_s⁻¹ becomes
  // p (1 − ½Δω̂), whose vector part changes by −½ (w Δω + v × Δω) (eq. 4.21): hence
  // ∂T/∂ω = −½ k_VC,torque (w I + ṽ) = −½ (k_VC,torque w I + T̃) — eq. 4.24 with
  // scalar(q_T) = −k_VC,torque w (eq. 4.25). p stays on its hemisphere for small Δω unless
  // w = 0.
  const Eigen::Quaterniond difference =
      to_positive_hemisphere(manipulandum.orientation * simulation.orientation.conjugate());
  wrench.linear_torque = springs.torque_stiffness * difference.vec();
  const Eigen::Matrix3d linear_by_rotation =
      -0.5 * (springs.torque_stiffness * difference.w() * Eigen::Matrix3d::Identity() +
              cross_matrix(wrench.linear_torque));
  const SaturatedVector torque = saturate(wrench.linear_torque, springs.saturation_torque);
  wrench.torque = torque.value;
  wrench.torque_by_rotation = torque.jacobian * linear_by_rotation;
  wrench.torque_saturated = torque.saturated;
  return wrench;
}

}  // namespace khz::haptic
