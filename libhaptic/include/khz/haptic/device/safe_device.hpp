#pragma once
// The safety layer every device goes through: clamping, a watchdog, disconnect handling, and the
// mapping between the device workspace and the virtual world (scaling and button-held indexing,
// thesis §4.5).

#include <khz/haptic/common.hpp>
#include <khz/haptic/device/device.hpp>
#include <khz/haptic/device/passivity_controller.hpp>
#include <khz/haptic/export.hpp>

#include <cstdint>
#include <limits>

namespace khz::haptic {

/// How device poses become virtual-world poses (thesis §4.5, eq. 4.27). With the offset (R, t):
///
///     x_virtual = t + R · (scale · x_device),   q_virtual = R · q_device,
///     v_virtual = scale · R · v_device,          ω_virtual = R · ω_device,
///     F_device  = force_scale · Rᵀ F_virtual,    T_device  = torque_scale · Rᵀ T_virtual.
///
/// `scale` is virtual metres per device metre, 1/α in the thesis's notation (α device millimetres
/// per simulation unit). Forces are not scaled by `scale`: the virtual world's forces are
/// rendered as newtons (thesis §4.5), times the optional force_scale / torque_scale (β).
struct KHZ_HAPTIC_API WorkspaceMapping {
  double scale = 1.0;         ///< Virtual metres per device metre, > 0.
  Pose offset;                ///< (R, t): device frame, scaled, → virtual world.
  double force_scale = 1.0;   ///< Device newtons per virtual newton, > 0.
  double torque_scale = 1.0;  ///< Device N·m per virtual N·m, > 0.

  /// @throws Error naming a non-positive or non-finite scale or a non-finite or non-unit offset.
  void validate() const;
};

/// Safety settings. Device limits come from the device's capabilities; these may only tighten
/// them.
struct KHZ_HAPTIC_API SafetyOptions {
  /// Force and torque magnitude limits (device units), applied with the device's own
  /// (the smaller wins). Infinity: the device's limits alone.
  double max_force = std::numeric_limits<double>::infinity();
  double max_torque = std::numeric_limits<double>::infinity();
  /// A cycle whose end_cycle() time exceeds its deadline by more than this (s, ≥ 0) is a miss.
  double deadline_tolerance = 0.0;
  /// After any write the layer zeroed (fault, indexing), the next `ramp_cycles` writes are
  /// scaled by 1/N, 2/N, …, N/N so output resumes without a jolt; after a deadline miss they
  /// move from the output the device held through the late cycle to the wrench asked for in the
  /// same N steps. 0 or 1: resume at once.
  int ramp_cycles = 0;
  /// "Wait for small force" (device N, ≥ 0; CHAI3D's waitForSmallForce): after open() and after
  /// a failed or invalid read, output stays zero until the force asked for is at most this, and
  /// only then resumes (through the ramp). A manipulandum that starts, or comes back from a
  /// device fault, inside an object feels nothing until it has moved out far enough, instead of
  /// a kick. Deadline misses and indexing keep the pose continuous and only ramp. Infinity
  /// disables the wait.
  double onset_force = 1.0;
  /// The same wait for the torque (device N·m, ≥ 0; 6-DOF output only): a manipulandum whose
  /// orientation starts far from the held object's would otherwise get the coupling's whole
  /// torque at once. Infinity leaves the torque out of the wait.
  double onset_torque = 0.05;
  /// Time-domain passivity control (Hannaford & Ryu 2002), off by default. An observer sums the
  /// work each held output has done on the hand (device units, translation and rotation apart);
  /// when the simulation has given back more than the hand put in, the next outputs get a damper
  /// along the device's velocity sized to take the excess back, at most the limits below. For
  /// loops whose settings inject energy (a coupling stiffer than the device can render at its
  /// rate, delays); the bundled settings are passive without it (docs/DEVICES.md).
  bool passivity_control = false;
  /// Largest damping the controller adds: device N·s/m and N·m·s/rad, > 0. Keep them below what
  /// the device renders stably as a damper at its rate.
  double passivity_max_damping = 10.0;
  double passivity_max_rotational_damping = 0.05;
  /// Bit index of the indexing (clutch) button; -1 disables workspace indexing.
  int index_button = -1;
  /// Index orientation too (true) or only position (false: orientation keeps following the
  /// device and only the translation offset is updated on release).
  bool index_orientation = true;
  /// Render zero while the index button is held (the user is repositioning the device).
  bool zero_output_while_indexing = true;

  /// @throws Error naming a negative or NaN limit or tolerance, a negative ramp, a passivity
  ///         damping limit that is not finite and > 0, an index button outside [-1, 31].
  void validate() const;
};

/// Counters since construction or the last reset_statistics().
struct SafetyStatistics {
  std::uint64_t reads = 0;
  std::uint64_t read_failures = 0;   ///< The device's read() failed (disconnect, error).
  std::uint64_t invalid_inputs = 0;  ///< A reading with a non-finite or non-unit pose, or a
                                     ///< non-finite velocity or time.
  std::uint64_t writes = 0;
  std::uint64_t clamped_writes = 0;           ///< Force or torque scaled down to its limit.
  std::uint64_t zeroed_writes = 0;            ///< Zero sent because of a fault (any reason below).
  std::uint64_t invalid_outputs = 0;          ///< The wrench given to write() was not finite.
  std::uint64_t deadline_misses = 0;          ///< Cycles that ended after deadline + tolerance.
  std::uint64_t indexed_cycles = 0;           ///< Reads with the index button held.
  std::uint64_t device_write_failures = 0;    ///< The device's write() returned false.
  std::uint64_t passivity_damped_writes = 0;  ///< Writes the passivity controller damped.
};

/// What happened to the last write, as bits (SafeDevice::last_write_events()).
enum SafetyEvent : std::uint32_t {
  safety_clamped_force = 1u << 0,
  safety_clamped_torque = 1u << 1,
  safety_zeroed_read_failure = 1u << 2,  ///< The cycle's read failed or was invalid.
  safety_zeroed_invalid_output = 1u << 3,
  /// The previous cycle missed its deadline: this write starts from what the device held.
  safety_after_deadline_miss = 1u << 4,
  safety_zeroed_indexing = 1u << 5,
  safety_ramping = 1u << 6,  ///< On the ramp after a zeroed write or a deadline miss.
  /// Zero: waiting, after the start or a failed read, for the force and torque to fall to
  /// onset_force and onset_torque.
  safety_waiting_for_small_force = 1u << 7,
  /// The passivity controller added damping (SafetyOptions::passivity_control).
  safety_passivity_damping = 1u << 8,
};

/// The layer between the haptic loop and a Device. Every cycle:
///
///     safe.begin_cycle(deadline);          // optional: arms the watchdog for this cycle
///     DeviceState s; safe.read(s);         // virtual-world pose; false → s.valid false
///     Wrench w = ...;                      // computed from s (any value, even NaN)
///     safe.write(w);                       // mapped, checked, clamped, sent
///     safe.end_cycle(now);                 // a late cycle: the next write slews
///
/// Guarantees, each within the cycle it is detected in: a failed or invalid read (disconnect,
/// NaN pose) makes that cycle's write send zero; a non-finite wrench is replaced by zero; force
/// and torque never exceed their limits (scaled down along their own direction; torque is
/// dropped for 3-DOF output devices). A cycle that ends late (end_cycle after deadline +
/// tolerance) has left its output on the device for too long; the *next* write does not drop to
/// zero (a jolt, and the hand would sink into what it pressed) but moves from that held output to
/// the fresh wrench over SafetyOptions::ramp_cycles writes. Output resumes by itself when reads
/// succeed again, once the force and torque asked for are at most SafetyOptions::onset_force and
/// onset_torque, and through the
/// ramp if SafetyOptions::ramp_cycles > 1. Before the first good read, every write sends zero.
///
/// Threading: the same as Device (read/write/begin_cycle/end_cycle from the haptic thread only,
/// noexcept, no allocation). Settings and statistics are plain members: change or read them from
/// the haptic thread, or while the loop is stopped.
class KHZ_HAPTIC_API SafeDevice {
 public:
  /// Wraps `device` (not owned; it must outlive this object).
  /// @throws Error if the options, the mapping or the device's capabilities are invalid.
  explicit SafeDevice(Device& device, const SafetyOptions& options = {},
                      const WorkspaceMapping& mapping = {});

  /// Opens the device and restarts the safety state (zero output until a good read).
  void open();
  /// Sends zero, then closes the device.
  void close() noexcept;
  bool is_open() const noexcept { return m_device.is_open(); }

  /// Reads the device and maps the state into the virtual world. On failure (device read failed,
  /// non-finite or non-unit pose, non-finite velocity or time) returns false and leaves the last
  /// good virtual state in `state` with state.valid false.
  bool read(DeviceState& state) noexcept;
  /// Maps a virtual-world wrench to the device, applies the checks above and sends it. Returns
  /// the device's write() result.
  bool write(const Wrench& wrench) noexcept { return write(wrench, Wrench{}); }
  /// write(wrench) for an application whose wrench lags what it will render: while waiting for a
  /// small force, output also stays zero until `pending`'s force and torque (virtual world,
  /// scaled by the mapping like the wrench) are at most SafetyOptions::onset_force and
  /// onset_torque. A virtual coupling whose simulation object starts where the manipulandum is
  /// (a hand holding its body as it lies) asks for nothing in its first cycle even when the
  /// held body starts deep inside another: the contact wrench on the body, what the coupling
  /// will render once it has stretched, is the pending wrench then (World passes it). NaN counts
  /// as large. Outside the wait it has no effect.
  bool write(const Wrench& wrench, const Wrench& pending) noexcept;

  /// Starts a cycle with its deadline (s, on the loop's clock; the same clock as end_cycle()).
  void begin_cycle(double deadline) noexcept;
  /// Ends the cycle at time `now`. A non-finite time, or `now` > deadline + tolerance, is a
  /// miss. Without a preceding begin_cycle() it does nothing.
  void end_cycle(double now) noexcept;

  /// True while the index button is held (the virtual pose is frozen).
  bool indexing() const noexcept { return m_indexing; }
  /// The wrench last sent to the device (device axes, after every check).
  const Wrench& last_output() const noexcept { return m_last_output; }
  /// SafetyEvent bits of the last write.
  std::uint32_t last_write_events() const noexcept { return m_last_events; }
  const SafetyStatistics& statistics() const noexcept { return m_statistics; }
  /// The passivity observer since open() (J, device units; translation plus rotation): the work
  /// the hand has done on the simulation through the device. Kept whether or not
  /// SafetyOptions::passivity_control is on; below zero the simulation has injected energy.
  double observed_energy() const noexcept {
    return m_passivity.translational_energy() + m_passivity.rotational_energy();
  }
  void reset_statistics() noexcept { m_statistics = {}; }

  const WorkspaceMapping& mapping() const noexcept { return m_mapping; }
  /// Replaces the mapping as given (the virtual pose may jump). @throws Error if invalid.
  void set_mapping(const WorkspaceMapping& mapping);
  /// Changes the scale and moves the offset so the current virtual position stays where it is
  /// (the user can adjust α during the simulation, §4.5). @throws Error if not finite and > 0.
  void set_scale(double scale);

  const SafetyOptions& options() const noexcept { return m_options; }
  /// @throws Error if invalid.
  void set_options(const SafetyOptions& options);

  Device& device() noexcept { return m_device; }
  const DeviceCapabilities& capabilities() const noexcept { return m_device.capabilities(); }

 private:
  void restart() noexcept;
  void update_limits() noexcept;
  /// Sends `output` (device axes) with `events`, tracking zeroed writes and the ramp.
  bool send(const Wrench& output, std::uint32_t events) noexcept;

  Device& m_device;
  SafetyOptions m_options;
  WorkspaceMapping m_mapping;
  double m_force_limit = 0.0;
  double m_torque_limit = 0.0;

  DeviceState m_device_state;   // last raw reading
  DeviceState m_virtual_state;  // last good virtual state
  bool m_input_ok = false;      // the last read succeeded and was valid
  bool m_indexing = false;
  Pose m_frozen;  // virtual pose held while indexing

  double m_deadline = 0.0;
  bool m_cycle_open = false;
  bool m_pending_miss = false;
  int m_ramp_step = 0;  // writes since the last zeroed one or miss, capped at ramp_cycles
  Wrench m_ramp_from;   // where the ramp starts (device axes): zero, or the output held late
  bool m_waiting_for_small_force = true;  // since the start or the last failed read
  PassivityController m_passivity;

  Wrench m_last_output;
  std::uint32_t m_last_events = 0;
  SafetyStatistics m_statistics;
};

}  // namespace khz::haptic
