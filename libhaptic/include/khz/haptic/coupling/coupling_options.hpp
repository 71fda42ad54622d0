#pragma once
// What static virtual coupling is configured with (thesis §4.3–§4.10).

#include <khz/haptic/common.hpp>
#include <khz/haptic/coupling/coupling_wrench.hpp>
#include <khz/haptic/export.hpp>

#include <limits>
#include <numbers>

namespace khz::haptic {

/// The configuration of a VirtualCoupling. Simulation-world units (§4.5): m, rad, s, N, N·m.
/// +∞ switches a limit off.
struct KHZ_HAPTIC_API CouplingOptions {
  static constexpr double unlimited = std::numeric_limits<double>::infinity();

  /// k_VC (N/m) of eq. 4.13, finite and > 0.
  double stiffness = 500.0;
  /// k_VC,torque (N·m) of eq. 4.14, finite and > 0 (the small-angle stiffness is half of it per
  /// radian).
  double torque_stiffness = 1.0;
  /// α of §4.8 in [0, 1): each cycle moves the simulation object by (1 − α)(Δx, Δω). The thesis
  /// uses 0.5; larger values make surfaces sticky.
  double static_damping = 0.5;
  /// The haptic cycle (s), finite and > 0: turns the speed limits into per-cycle limits.
  double period = 1e-3;
  /// Largest speed (m/s) of the simulation object's grasp point (§4.6), > 0 or unlimited; the
  /// thesis uses 0.6 m/s.
  double max_speed = 0.6;
  /// Largest angular speed (rad/s) of the simulation object (§4.6), > 0 or unlimited; the thesis
  /// uses 360°/s.
  double max_angular_speed = 2.0 * std::numbers::pi;
  /// F_VC,max (N) of eq. 4.39, > 0 or unlimited: the plateau the coupling force on the
  /// simulation object saturates to (§4.9 sets it to the force of one point at the largest
  /// penetration allowed, e.g. k_C × half a voxel).
  double saturation_force = unlimited;
  /// The largest distance (m) from the grasp point to the haptic object's surface, > 0 or
  /// unlimited. The coupling torque saturates to F_VC,max × object_radius, the torque of the
  /// saturated force at the object's extremity (§4.9: a torque limit that ignores the object's
  /// size lets a lever push a contact deeper than the force limit does). Below that, a contact
  /// at the extremity stays within the force limit; and any saturated force applied anywhere on
  /// the object can still be balanced by the torque spring.
  double object_radius = unlimited;
  /// The device's largest force (N), > 0 or unlimited: §4.9 renders −k_VC (x_m − x_s) clamped
  /// to it, direction kept (8.5 N on the thesis's PHANToM).
  double max_rendered_force = unlimited;
  /// The device's largest torque (N·m), > 0 or unlimited: the unsaturated coupling torque is
  /// rendered, clamped to it.
  double max_rendered_torque = unlimited;
  /// The device's largest stable stiffness (N/m), > 0 or unlimited (0.6 N/mm on the thesis's
  /// PHANToM): stiffness must not exceed it, since k_VC bounds the stiffness rendered (§4.7,
  /// eq. 4.31).
  double device_max_stiffness = unlimited;
  /// ε of §4.10 in (0, 1): singular values below ε σ₁ count as degenerate (the thesis: 1e-3).
  double degenerate_threshold = 1e-3;
  /// Metres per radian ℓ in §4.10's SVD and eq. 4.41's snap: finite and > 0, or 0 (the
  /// default) for object_radius when that is set and otherwise 1 m (the thesis's system as it
  /// stands). The 6×6 system mixes N/m, N, N·m/rad; solving for (Δx, ℓ Δω) with the torque rows
  /// divided by ℓ makes every block N/m, so ε compares like with like. With ℓ = 1 m the
  /// rotations of a few-centimetre object look degenerate: they snap to the manipulandum and
  /// ignore contact torques. The object's size is the natural choice.
  double rotation_length = 0.0;

  /// ℓ as the solve uses it: rotation_length if > 0, else object_radius if finite, else 1 m.
  double effective_rotation_length() const noexcept {
    if (rotation_length > 0.0) return rotation_length;
    return object_radius < unlimited ? object_radius : 1.0;
  }

  /// The springs these options describe (torque plateau F_VC,max × object_radius).
  CouplingSprings springs() const noexcept;
  /// d_max of §4.6 (m per cycle): max_speed × period.
  double max_translation_per_cycle() const noexcept { return max_speed * period; }
  /// θ_max of §4.6 (rad per cycle): max_angular_speed × period.
  double max_rotation_per_cycle() const noexcept { return max_angular_speed * period; }

  /// @throws Error naming the first option out of range.
  void validate() const;
};

}  // namespace khz::haptic
