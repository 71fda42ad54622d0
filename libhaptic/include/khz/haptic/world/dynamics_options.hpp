#pragma once
// How a World moves its dynamic bodies: gravity, the step and when a body at rest sleeps.

#include <khz/haptic/export.hpp>

#include <Eigen/Core>

namespace khz::haptic {

/// The settings of a World's dynamic bodies (Body::dynamics), the same for all of them.
struct KHZ_HAPTIC_API DynamicsOptions {
  /// m/s², world frame. Acts on dynamic bodies only, free or grasped (a grasped body's weight is
  /// part of its hand's wrench); held and fixed bodies have no weight.
  Eigen::Vector3d gravity{0.0, 0.0, -9.81};
  /// The time a cycle steps them (s): the haptic loop's period.
  double time_step = 1e-3;
  /// β (s): the damping of a free body's contacts with fixed (or sleeping) bodies is β times
  /// their stiffness (Rayleigh's stiffness-proportional damping). For a body of mass m on a
  /// contact of stiffness k it gives the damping ratio ζ = β √(k/m) / 2 and so a restitution of
  /// about exp(−π ζ / √(1 − ζ²)): 0.005 s is ζ = 0.35 and 0.3 for 1 kg on the 20 kN/m of a
  /// 2,000 N/m point stiffness with L = 10. 0 leaves only the step's own damping, and a dropped
  /// body bounces for a long time. Contacts with held and other dynamic bodies have only the
  /// step's own damping.
  double contact_damping = 0.005;
  /// A free body sleeps once, for `sleep_time`, its centre has moved slower than this and its
  /// points have turned about it slower than this (angular speed × radius of gyration) (m/s).
  /// A sleeping body is neither stepped nor queried against bodies that do not move: it costs
  /// nothing and cannot drift. It wakes when a moving body touches it, stops touching it, or a
  /// hand grasps or releases it; woken by a touch, it moves from the next cycle, once all its
  /// contacts are queried again. 0 never sleeps.
  double sleep_speed = 1e-3;
  double sleep_time = 0.25;  ///< s, ≥ 0.

  /// @throws Error naming the first value out of range: gravity not finite, time_step not
  ///         finite and > 0, contact_damping, sleep_speed or sleep_time not finite and ≥ 0.
  void validate() const;
};

}  // namespace khz::haptic
