#include <khz/haptic/device/passivity_controller.hpp>

#include <khz/haptic/coupling/rotation_vector.hpp>

#include <algorithm>
#include <cmath>

namespace khz::haptic {
namespace {

/// Deficits smaller than this (J) are round-off in the observer's sums, not energy anyone could
/// feel (a 0.45 kg device and hand at 0.1 mm/s carry 2e-9 J): no damping for them.
constexpr double negligible_energy = 1e-9;

/// The damping that takes back an energy deficit −energy over one period at `speed`'s square,
/// at most `limit`; 0 without a deficit or without motion.
double damping_for(double energy, double squared_speed, double step, double limit) noexcept {
  if (!(energy < -negligible_energy) || !(squared_speed > 0.0) || !(step > 0.0)) return 0.0;
  return std::min(-energy / (step * squared_speed), limit);
}

}  // namespace

void PassivityController::restart() noexcept {
  m_has_previous = false;
  m_step = 0.0;
  m_velocity.setZero();
  m_angular_velocity.setZero();
  m_energy_force = 0.0;
  m_energy_torque = 0.0;
}

void PassivityController::observe(const Pose& pose, double time, const Wrench& held,
                                  double period) noexcept {
  if (m_has_previous) {
    const Eigen::Vector3d moved = pose.position - m_previous.position;
    const Eigen::Vector3d turned =
        rotation_vector(pose.orientation * m_previous.orientation.conjugate());
    m_energy_force -= held.force.dot(moved);
    m_energy_torque -= held.torque.dot(turned);
    const double elapsed = time - m_previous_time;
    m_step = elapsed > 0.0 ? elapsed : period;
    m_velocity = moved / m_step;
    m_angular_velocity = turned / m_step;
  }
  m_previous = pose;
  m_previous_time = time;
  m_has_previous = true;
}

bool PassivityController::damp(Wrench& output) const noexcept {
  const double alpha = damping_for(m_energy_force, m_velocity.squaredNorm(), m_step, m_max_damping);
  const double beta = damping_for(m_energy_torque, m_angular_velocity.squaredNorm(), m_step,
                                  m_max_rotational_damping);
  output.force -= alpha * m_velocity;
  output.torque -= beta * m_angular_velocity;
  return alpha > 0.0 || beta > 0.0;
}

}  // namespace khz::haptic
