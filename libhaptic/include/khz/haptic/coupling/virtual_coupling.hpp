#pragma once
// Static virtual coupling (thesis ch. 4): the simulation object that follows the manipulandum
// under coupling springs and contact, and the wrench rendered to the device.

#include <khz/contact/query/contact_wrench.hpp>
#include <khz/haptic/common.hpp>
#include <khz/haptic/coupling/coupling_options.hpp>
#include <khz/haptic/export.hpp>

namespace khz::haptic {

/// What one cycle of VirtualCoupling::step produced.
struct CouplingStep {
  /// The simulation object after the step: query contact here next cycle.
  Pose simulation;
  /// The wrench for the device (N, N·m about the tool point): the negative of the unsaturated
  /// coupling wrench on the simulation object at its new pose (Newton's third law, §4.1; §4.9
  /// renders −k_VC (x_m − x_s) even where the simulation's force saturates), clamped to the
  /// device's limits with its direction kept. Zero when !valid.
  Wrench rendered;
  /// F_VC, T_VC on the simulation object at its new pose (saturated, eq. 4.39).
  Wrench coupling;
  /// F_C + F_VC, T_C + T_VC at the pose the step started from (eq. 4.1–4.2's net wrench, N and
  /// N·m about the grasp point): how far from equilibrium the previous step left the simulation
  /// object, with this cycle's manipulandum and contact.
  Wrench residual;
  /// Dimension of §4.10's degenerate subspace this cycle (0: the system had full rank).
  int degenerate_dimension = 0;
  /// The coupling force or torque was beyond its linear part (eq. 4.39) when the step was solved.
  bool coupling_saturated = false;
  bool force_clamped = false;          ///< The rendered force hit max_rendered_force.
  bool torque_clamped = false;         ///< The rendered torque hit max_rendered_torque.
  bool speed_limited = false;          ///< Δx was shortened to max_translation_per_cycle (§4.6).
  bool angular_speed_limited = false;  ///< Δω was shortened to max_rotation_per_cycle (§4.6).
  /// False if the manipulandum pose or the contact result was not finite (or the manipulandum's
  /// quaternion was zero): the state did not change and nothing is rendered.
  bool valid = false;
};

/// Static virtual coupling with static damping, speed limits, saturation and degenerate-rank
/// handling (thesis §4.1–§4.10). It holds the simulation object's pose; every haptic cycle:
///
///   1. read the manipulandum pose (device pose → simulation world, §4.5: the loop's job);
///   2. query contact with the haptic object at simulation_pose() (grasp point = its position),
///      giving the force and torque on the haptic object and their gradients;
///   3. step(manipulandum, contact): solves the linearized equilibrium of the coupling and
///      contact (eq. 4.1–4.2) by §4.10's SVD, damps (§4.8) and limits (§4.6) the motion, moves
///      the simulation object and returns the wrench for the device;
///   4. send CouplingStep::rendered to the device, and the contact result's reduced forces to
///      the deformable objects' integrators.
///
/// The contact gradients are used as ContactWrench gives them (thesis §4.2's construction);
/// the coupling's own gradients are for world-axis rotations about the grasp point. The
/// speed limits bound how far the simulation object moves per cycle (max_translation_per_cycle,
/// max_rotation_per_cycle), which is what a contact query's temporal coherence needs declared.
///
/// step() allocates nothing, throws nothing and takes ~µs; one instance per haptic object, used
/// by one thread.
class KHZ_HAPTIC_API VirtualCoupling {
 public:
  using Options = CouplingOptions;

  /// @param simulation the simulation object's starting pose (usually the manipulandum's).
  /// @throws Error if the options fail validate() or the pose is not finite or its quaternion
  ///         is zero.
  explicit VirtualCoupling(const Options& options, const Pose& simulation = {});

  const Options& options() const noexcept { return m_options; }
  /// The pose the next contact query must be evaluated at.
  const Pose& simulation_pose() const noexcept { return m_simulation; }

  /// One haptic cycle.
  /// @param manipulandum the manipulandum's grasp point (m, simulation world) and orientation
  ///        (a nonzero quaternion, normalized here; either hemisphere).
  /// @param contact the contact query at simulation_pose(): force (N) and torque (N·m about the
  ///        grasp point) on the haptic object, ∂F/∂x, ∂F/∂ω, ∂T/∂x, ∂T/∂ω. Only these are read.
  CouplingStep step(const Pose& manipulandum, const contact::ContactWrench& contact) noexcept;

  /// Puts the simulation object at `simulation` (e.g. the manipulandum's pose when the loop
  /// starts or after workspace indexing). Returns false and changes nothing if the pose is not
  /// finite or its quaternion is zero.
  bool reset(const Pose& simulation) noexcept;

 private:
  Options m_options;
  CouplingSprings m_springs;
  Pose m_simulation;
};

}  // namespace khz::haptic
