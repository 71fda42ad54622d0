#include <khz/haptic/coupling/equilibrium.hpp>
#include <khz/haptic/coupling/rotation_vector.hpp>
#include <khz/haptic/coupling/virtual_coupling.hpp>

#include "clamp_magnitude.hpp"

#include <cmath>

namespace khz::haptic {
namespace {

// A finite position and a finite quaternion that can be normalized.
bool usable(const Pose& pose) noexcept {
  const double norm2 = pose.orientation.squaredNorm();
  return pose.position.allFinite() && pose.orientation.coeffs().allFinite() && norm2 > 0.0 &&
         std::isfinite(norm2);
}

bool finite(const contact::ContactWrench& contact) noexcept {
  return contact.force.allFinite() && contact.torque.allFinite() &&
         contact.force_by_translation.allFinite() && contact.force_by_rotation.allFinite() &&
         contact.torque_by_translation.allFinite() && contact.torque_by_rotation.allFinite();
}

}  // namespace

VirtualCoupling::VirtualCoupling(const Options& options, const Pose& simulation)
    : m_options(options) {
  m_options.validate();
  m_springs = m_options.springs();
  if (!reset(simulation)) {
    throw Error(
        "VirtualCoupling: the starting simulation pose must be finite with a nonzero "
        "quaternion");
  }
}

bool VirtualCoupling::reset(const Pose& simulation) noexcept {
  if (!usable(simulation)) return false;
  m_simulation.position = simulation.position;
  m_simulation.orientation = simulation.orientation.normalized();
  return true;
}

CouplingStep VirtualCoupling::step(const Pose& manipulandum,
                                   const contact::ContactWrench& contact) noexcept {
  CouplingStep result;
  result.simulation = m_simulation;
  if (!usable(manipulandum) || !finite(contact)) return result;
  const Pose target_pose{manipulandum.position, manipulandum.orientation.normalized()};

  // Eq. 4.1–4.2 at the current simulation pose, solved for (Δx, ℓΔω) with the torque rows
  // divided by ℓ (CouplingOptions::effective_rotation_length(); ℓ = 1 m is the thesis's system
  // as it stands).
  const CouplingWrench before = coupling_wrench(target_pose, m_simulation, m_springs);
  const EquilibriumSystem system = equilibrium_system(before, contact);
  const double length = m_options.effective_rotation_length();
  Vector6d scale;
  scale << 1.0, 1.0, 1.0, 1.0 / length, 1.0 / length, 1.0 / length;
  Vector6d snap;  // eq. 4.41's manipulandum − simulation, in the scaled unknowns
  snap << target_pose.position - m_simulation.position,
      length * rotation_vector(target_pose.orientation * m_simulation.orientation.conjugate());
  const EquilibriumSolution solution = solve_equilibrium(
      scale.asDiagonal() * system.jacobian * scale.asDiagonal(),
      -scale.cwiseProduct(system.net_wrench), snap, m_options.degenerate_threshold);

  // Static damping (§4.8), then the per-cycle limits (§4.6, applied to x_nd + x_d as §4.10 says).
  const Vector6d motion = (1.0 - m_options.static_damping) * scale.cwiseProduct(solution.step);
  Eigen::Vector3d translation = motion.head<3>();
  Eigen::Vector3d rotation = motion.tail<3>();
  const bool speed_limited =
      detail::clamp_magnitude(translation, m_options.max_translation_per_cycle());
  const bool angular_speed_limited =
      detail::clamp_magnitude(rotation, m_options.max_rotation_per_cycle());
  if (!translation.allFinite() || !rotation.allFinite()) return result;  // overflow in the solve

  m_simulation.position += translation;
  m_simulation.orientation =
      (rotation_quaternion(rotation) * m_simulation.orientation).normalized();

  // What the device feels is the coupling at the new pose, with the opposite sign (§4.1).
  const CouplingWrench after = coupling_wrench(target_pose, m_simulation, m_springs);
  result.simulation = m_simulation;
  result.rendered.force = -after.linear_force;
  result.rendered.torque = -after.linear_torque;
  result.force_clamped =
      detail::clamp_magnitude(result.rendered.force, m_options.max_rendered_force);
  result.torque_clamped =
      detail::clamp_magnitude(result.rendered.torque, m_options.max_rendered_torque);
  result.coupling.force = after.force;
  result.coupling.torque = after.torque;
  result.residual.force = system.net_wrench.head<3>();
  result.residual.torque = system.net_wrench.tail<3>();
  result.degenerate_dimension = solution.degenerate_dimension;
  result.coupling_saturated = before.force_saturated || before.torque_saturated;
  result.speed_limited = speed_limited;
  result.angular_speed_limited = angular_speed_limited;
  result.valid = true;
  return result;
}

}  // namespace khz::haptic
