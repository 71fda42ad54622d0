#pragma once
// Time-domain passivity control at the device port (Hannaford & Ryu, "Time-domain passivity
// control of haptic interfaces", IEEE T-RA 18(1), 2002): an observer of the energy the
// simulation has given the hand, and a damper that takes any excess back. SafeDevice runs one
// (SafetyOptions::passivity_control); a program with its own device layer may too.

#include <khz/haptic/common.hpp>
#include <khz/haptic/export.hpp>

#include <Eigen/Core>

namespace khz::haptic {

/// One controller per device, in device axes and units. Translation and rotation are two ports
/// with an observer each (J):
///
///     E_k = − Σ_{j<k} F_j · Δx_j   and   − Σ_{j<k} T_j · Δθ_j,
///
/// F_j, T_j the wrench the device held from reading j to reading j + 1 and Δx_j, Δθ_j its motion
/// in between: exactly the work a zero-order-held output does on the hand. E < 0 means the
/// simulation has returned more energy than the hand put in, which no passive object does; the
/// next output then gets a damper α along the last period's velocity v,
///
///     F ← F − α v,   α = min(−E / (Δt ‖v‖²), α_max),
///
/// sized to dissipate the excess in one period if the motion goes on (the same for torque).
/// Deficits below 1e-9 J are round-off and get no damper.
/// The energy it actually takes is observed in later periods through the wrench sent, so a
/// clamped or ramped output is accounted for. All noexcept, no allocation.
class KHZ_HAPTIC_API PassivityController {
 public:
  /// Limits of α: N·s/m and N·m·s/rad (device units), ≥ 0; 0 until set, which damps nothing.
  void set_limits(double max_damping, double max_rotational_damping) noexcept {
    m_max_damping = max_damping;
    m_max_rotational_damping = max_rotational_damping;
  }
  /// Forgets the motion and restarts both observers at 0 (after open()).
  void restart() noexcept;
  /// Forgets the last reading only: motion across a gap in the readings (a fault) is not
  /// observed, the wrench held then being zero.
  void interrupt() noexcept { m_has_previous = false; }
  /// Observes a good reading (device axes; time in s) with `held` the wrench sent since the last
  /// one. `period` (s, > 0) stands in for the time step when the device's clock does not advance.
  void observe(const Pose& pose, double time, const Wrench& held, double period) noexcept;
  /// Adds the damping the observers ask for to `output` (device axes). Returns true if it did.
  bool damp(Wrench& output) const noexcept;

  /// The two observers (J).
  double translational_energy() const noexcept { return m_energy_force; }
  double rotational_energy() const noexcept { return m_energy_torque; }

 private:
  double m_max_damping = 0.0;
  double m_max_rotational_damping = 0.0;
  bool m_has_previous = false;
  Pose m_previous;
  double m_previous_time = 0.0;
  double m_step = 0.0;                                   // Δt of the last observed period (s)
  Eigen::Vector3d m_velocity = Eigen::Vector3d::Zero();  // m/s
  Eigen::Vector3d m_angular_velocity = Eigen::Vector3d::Zero();  // rad/s
  double m_energy_force = 0.0;
  double m_energy_torque = 0.0;
};

}  // namespace khz::haptic
