#pragma once
// The motion of a free rigid body at the haptic rate (issue 20): a linearly implicit Euler step
// that uses the contact gradients the query already returns, so it stays stable at contact
// stiffness.

#include <khz/haptic/export.hpp>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace khz::haptic {

/// What moves a free rigid body: its mass, where its centre of mass is and its inertia.
struct KHZ_HAPTIC_API RigidInertia {
  double mass = 1.0;                                 ///< kg, finite and > 0.
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();  ///< Centre of mass, body frame (m).
  /// Inertia tensor about the centre, body axes (kg·m²): symmetric positive definite.
  Eigen::Matrix3d inertia = Eigen::Matrix3d::Identity();

  /// @throws Error naming the first value out of range.
  void validate() const;
};

/// A rigid body that is neither held nor fixed: its pose, the velocity of its centre of mass and
/// its angular momentum (world frame), stepped by
///
///   (M − h² K) Δu = h (f + h K u),   u = [v; ω],   v⁺ = v + Δv,   L⁺ = L + (R I Rᵀ) Δω,
///   c⁺ = c + h v⁺,   R⁺ = exp(h (ω + Δω)) R,
///
/// with ω = (R I Rᵀ)⁻¹ L, M = diag(m 1, R I Rᵀ), f = [F + m g; T] and K the 6×6 stiffness of the
/// wrench, [∂F/∂x ∂F/∂ω; ∂T/∂x ∂T/∂ω] for a motion of the body about its centre of mass: the
/// contact query's gradients with the grasp point at the centre of mass
/// (contact::ContactWrench). This is backward Euler linearized once (Baraff and Witkin's step
/// for stiff cloth): a contact spring of any stiffness is integrated without growing energy, at
/// the price of some numerical damping, which also lets a body come to rest. The rotation keeps
/// the angular momentum L rather than ω, so without torque L is conserved exactly, and ω follows
/// from it as the body turns (the gyroscopic effect, with no explicit ω × Iω term to drift).
///
/// step() allocates nothing, takes no lock, throws nothing.
class KHZ_HAPTIC_API FreeBodyMotion {
 public:
  /// @param pose world ← body at the start.
  /// @param velocity of the centre of mass (m/s, world); @param angular_velocity (rad/s, world).
  /// @throws Error if `inertia` fails validate() or a value is not finite.
  FreeBodyMotion(const RigidInertia& inertia, const Eigen::Isometry3d& pose,
                 const Eigen::Vector3d& velocity = Eigen::Vector3d::Zero(),
                 const Eigen::Vector3d& angular_velocity = Eigen::Vector3d::Zero());

  /// One step of `h` seconds under gravity `gravity` (m/s², world) and a wrench on the body:
  /// `force` (N) at the centre of mass and `torque` (N·m) about it, world frame, with its
  /// stiffness `stiffness` as above (zero for a wrench that does not depend on the pose).
  /// @returns false, leaving the state unchanged, if h ≤ 0, an input is not finite, or the
  ///          step's matrix is singular.
  bool step(double h, const Eigen::Vector3d& force, const Eigen::Vector3d& torque,
            const Eigen::Matrix<double, 6, 6>& stiffness, const Eigen::Vector3d& gravity) noexcept;

  const RigidInertia& inertia() const noexcept { return m_inertia; }
  /// World ← body.
  const Eigen::Isometry3d& pose() const noexcept { return m_pose; }
  /// The centre of mass in the world (m).
  Eigen::Vector3d centre() const noexcept { return m_pose * m_inertia.centre; }
  const Eigen::Vector3d& velocity() const noexcept { return m_velocity; }
  /// ω = (R I Rᵀ)⁻¹ L (rad/s, world).
  Eigen::Vector3d angular_velocity() const noexcept;
  /// The inertia tensor about the centre of mass in world axes, R I Rᵀ (kg·m²).
  Eigen::Matrix3d world_inertia() const noexcept;
  /// ½ m v² + ½ ωᵀ (R I Rᵀ) ω (J).
  double kinetic_energy() const noexcept;
  /// m v (kg·m/s).
  Eigen::Vector3d momentum() const noexcept { return m_inertia.mass * m_velocity; }
  /// About the world origin: c × m v + L, L = R I Rᵀ ω about the centre of mass (kg·m²/s).
  Eigen::Vector3d angular_momentum() const noexcept;
  /// Places the body (e.g. released from a hand): pose and velocities as the constructor takes
  /// them. Non-finite values leave it unchanged and return false.
  bool set_state(const Eigen::Isometry3d& pose, const Eigen::Vector3d& velocity,
                 const Eigen::Vector3d& angular_velocity) noexcept;

 private:
  RigidInertia m_inertia;
  Eigen::Isometry3d m_pose;
  Eigen::Matrix3d m_inverse_inertia;  // I⁻¹, body axes
  Eigen::Vector3d m_velocity;
  Eigen::Vector3d m_spin;  // L about the centre of mass, world
};

}  // namespace khz::haptic
