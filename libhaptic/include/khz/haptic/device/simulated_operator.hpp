#pragma once
// A virtual device plus hand: the device's end effector is a rigid body driven by the rendered
// wrench and by a hand (spring–damper) whose anchor follows a scripted target. It closes the
// haptic loop at the device's rate, so stability can be tested without hardware.

#include <khz/haptic/common.hpp>
#include <khz/haptic/device/device.hpp>
#include <khz/haptic/export.hpp>

#include <Eigen/Core>

#include <algorithm>
#include <cstdint>
#include <functional>
#include <vector>

namespace khz::haptic {

/// The device's own dynamics at the tool point: apparent mass and rotational inertia, viscous
/// friction to ground. Gravity is taken as compensated (as the devices do).
struct DeviceDynamics {
  double mass = 0.15;                 ///< kg
  double inertia = 1e-4;              ///< kg·m², isotropic about the tool point
  double damping = 0.5;               ///< N·s/m
  double rotational_damping = 0.001;  ///< N·m·s/rad
};

/// The operator's hand. Its mass and inertia move with the device (the hand grips the stylus);
/// its muscles and tissue are a spring–damper from the grip to an anchor that follows the target:
///
///     F_hand = k_h (x_target − x) + b_h (v_target − v)
///     T_hand = k_h,rot θ(q_target q⁻¹) + b_h,rot (ω_target − ω)      (θ: rotation vector)
struct HandModel {
  double mass = 0.3;                  ///< kg
  double inertia = 5e-4;              ///< kg·m²
  double stiffness = 300.0;           ///< k_h, N/m
  double damping = 6.0;               ///< b_h, N·s/m
  double rotational_stiffness = 1.5;  ///< k_h,rot, N·m/rad
  double rotational_damping = 0.03;   ///< b_h,rot, N·m·s/rad
};

struct KHZ_HAPTIC_API SimulatedOperatorOptions {
  /// Round values in the range of a Phantom Premium 1.5 6-DOF (the thesis's device): 6-DOF in and
  /// out, 8.5 N (the force the thesis clamps to, §4.9), 0.5 N·m, 3500 N/m, a 0.38 × 0.27 ×
  /// 0.19 m box around the origin, 1 kHz. Illustrative, not the vendor's data sheet.
  static DeviceCapabilities phantom_premium_like();

  DeviceCapabilities capabilities = phantom_premium_like();
  DeviceDynamics device;
  HandModel hand;
  /// Device pose at open(); when start_at_target, the target's pose at time 0 instead.
  Pose initial_pose;
  bool start_at_target = true;
  /// Integration steps per haptic period (≥ 1). The device is a continuous system sampled by the
  /// loop: with several substeps the held wrench acts on dynamics that evolve within the period,
  /// so the sampled-data effects of real hardware (energy a stiff wall gains per contact) show.
  int substeps = 10;

  /// Checks the capabilities, positive masses and inertias, non-negative stiffnesses and
  /// dampings, and the stability of the integration at h = 1 / nominal_rate (see
  /// SimulatedOperator). @throws Error naming the value or the violated condition.
  void validate() const;
};

/// The target pose of the hand's anchor at a time (s). Called once per step from read(): it must
/// not allocate, throw or block.
using TargetFunction = std::function<Pose(double time)>;

/// The buttons the operator holds at a time (s): bit i set while button i is held (e.g. a
/// World hand's grasp_button). Called once per read(): it must not allocate, throw or block.
using ButtonFunction = std::function<std::uint32_t(double time)>;

/// A pose at a time, for keyframe_target(), and the buttons held from then on, for
/// keyframe_buttons().
struct Keyframe {
  double time = 0.0;
  Pose pose;
  std::uint32_t buttons = 0;  ///< Held from `time` until the next keyframe's (bit i: button i).
};

/// A piecewise-linear target through the keyframes (linear position, slerp orientation), held
/// constant before the first and after the last.
/// @throws Error if there are no keyframes, times do not strictly increase, or a pose is invalid.
KHZ_HAPTIC_API TargetFunction keyframe_target(std::vector<Keyframe> keyframes);

/// The buttons of the last keyframe at or before the time (none before the first): a scripted
/// operator's button presses, e.g. to grasp and release. Empty (no function) when no keyframe
/// holds a button, so an operator without presses pays nothing per read.
/// @throws Error as keyframe_target().
KHZ_HAPTIC_API ButtonFunction keyframe_buttons(std::vector<Keyframe> keyframes);

/// The virtual device + hand. Each read() after the first advances the simulation by one haptic
/// period T = 1 / capabilities.nominal_rate with the wrench last written (held for the whole
/// period, like a real device's output stage: zero-order hold), then reports the new state; the
/// first read() after open() reports the initial state at time 0. write() stores the wrench for
/// the next period, saturated to the capabilities (motor limits; torque dropped for 3-DOF
/// output).
///
/// Integration: `substeps` steps of semi-implicit (symplectic) Euler per period, h = T/substeps:
/// v ← v + h a(x, v), x ← x + h v, the orientation advanced by the rotation vector h ω (world
/// axes). With total mass m, stiffness k and damping b acting on the device, a step is stable
/// iff h² k/m + 2 h b/m < 4 (for b = 0: h < 2/ω_n); validate() checks this for the hand
/// (translation and rotation). A wall rendered through write() is a spring sampled once per
/// period T and held, exactly as on hardware: besides the bound above (with the wall's stiffness
/// added to k, at the period T), it is passive only if the device and hand damping exceed
/// k_wall T / 2 (Colgate's condition), and otherwise gains energy at every contact. That is what
/// this class lets one test.
///
/// Faults for tests: inject_invalid_pose() makes reads report a NaN position while claiming to
/// be valid; inject_disconnect() makes reads and writes fail, and the device renders zero until
/// it is written to after reconnecting. The simulation keeps running through both.
/// inject_stall() makes the next read come late, as after a stalled loop.
class KHZ_HAPTIC_API SimulatedOperator final : public Device {
 public:
  /// `buttons`: what read() reports as held (none when empty).
  /// @throws Error as SimulatedOperatorOptions::validate(), or if the target is empty.
  explicit SimulatedOperator(TargetFunction target, const SimulatedOperatorOptions& options = {},
                             ButtonFunction buttons = {});

  /// Resets the time to 0 and the device to its initial pose at rest, no wrench, no faults.
  void open() override;
  void close() noexcept override;
  bool is_open() const noexcept override { return m_open; }
  const DeviceCapabilities& capabilities() const noexcept override {
    return m_options.capabilities;
  }
  bool read(DeviceState& state) noexcept override;
  /// False (and zero is rendered) for a non-finite wrench or while disconnected.
  bool write(const Wrench& wrench) noexcept override;

  /// The next `reads` reads report a NaN position (and return true, state.valid true).
  void inject_invalid_pose(int reads) noexcept { m_invalid_reads = reads; }
  /// The next `reads` reads fail and writes are refused until a read succeeds again; output
  /// stops at once and resumes with the next write after that.
  void inject_disconnect(int reads) noexcept;
  /// The next read advances the simulation by `periods` more periods (≥ 0) with the wrench last
  /// written held throughout: the loop stalled (a preempted or blocked thread) while the
  /// device's output stage kept its last command.
  void inject_stall(int periods) noexcept { m_stalled_periods = std::max(periods, 0); }

  double time() const noexcept { return m_time; }
  const Pose& pose() const noexcept { return m_pose; }
  const Eigen::Vector3d& linear_velocity() const noexcept { return m_linear_velocity; }
  const Eigen::Vector3d& angular_velocity() const noexcept { return m_angular_velocity; }
  /// The wrench acting on the device now (after saturation; zero while disconnected).
  const Wrench& applied_wrench() const noexcept { return m_applied; }
  /// Where the hand's anchor is now.
  Pose target_pose() const { return m_target(m_time); }
  /// ½ m v² + ½ I ω² of device and hand (J).
  double kinetic_energy() const noexcept;
  /// ½ k_h |x_target − x|² + ½ k_h,rot |θ|² (J).
  double hand_energy() const;
  /// Writes refused because the wrench was not finite.
  std::uint64_t rejected_writes() const noexcept { return m_rejected_writes; }

 private:
  void step() noexcept;

  TargetFunction m_target;
  SimulatedOperatorOptions m_options;
  ButtonFunction m_buttons;
  double m_step = 0.0;  // integration step h = T / substeps (s)
  bool m_open = false;
  bool m_started = false;  // the first read has happened
  double m_time = 0.0;
  std::uint64_t m_steps = 0;  // integration steps since open()
  Pose m_pose;
  Eigen::Vector3d m_linear_velocity = Eigen::Vector3d::Zero();
  Eigen::Vector3d m_angular_velocity = Eigen::Vector3d::Zero();
  Pose m_previous_target;
  Wrench m_applied;
  int m_invalid_reads = 0;
  int m_disconnected_reads = 0;
  int m_stalled_periods = 0;  // extra periods the next read advances
  bool m_connected = true;    // false from inject_disconnect() to the next successful read
  std::uint64_t m_rejected_writes = 0;
};

}  // namespace khz::haptic
