#pragma once
// The device interface: what libhaptic needs from a haptic device (or anything that stands in for
// one), and nothing more. Hardware enters Kilohertz only through this class; see docs/DEVICES.md.

#include <khz/haptic/common.hpp>
#include <khz/haptic/export.hpp>

#include <Eigen/Core>

#include <cstdint>
#include <limits>
#include <string>

namespace khz::haptic {

/// What a device can sense and display. Device-frame quantities: SI units in the device's own
/// axes (metres, newtons, newton-metres), before any workspace scaling (SafeDevice does that).
struct KHZ_HAPTIC_API DeviceCapabilities {
  std::string name = "device";  ///< For messages and logs.
  int input_dof = 6;           ///< 3 (position only; read() reports the identity orientation) or 6.
  int output_dof = 6;          ///< 0 (input only), 3 (force only; torques are dropped) or 6.
  double max_force = 0.0;      ///< Largest force magnitude the device may render (N), > 0.
  double max_torque = 0.0;     ///< Largest torque magnitude (N·m), > 0 when output_dof is 6.
  double max_stiffness = 0.0;  ///< Largest stable rendered stiffness (N/m), > 0; advisory: the
                               ///< coupling uses it to choose its spring, nothing clamps it.
  /// Reachable box of the tool point in device axes (m): minimum and maximum corners.
  Eigen::Vector3d workspace_min = Eigen::Vector3d::Constant(-0.1);
  Eigen::Vector3d workspace_max = Eigen::Vector3d::Constant(0.1);
  /// Reach from the box centre (m); infinity when the box alone describes the workspace.
  double workspace_radius = std::numeric_limits<double>::infinity();
  double nominal_rate = 1000.0;  ///< Servo rate the device is meant to run at (Hz), > 0.

  /// True if the device-frame point `p` (m) lies in the box and within the radius.
  bool contains(const Eigen::Vector3d& p) const noexcept;
  /// @throws Error naming the first invalid field (DOF counts, non-positive limits or rate,
  ///         an empty box, a non-positive radius).
  void validate() const;
};

/// One reading of a device, in device axes (SafeDevice hands out the same struct in the virtual
/// world). Fields a device cannot sense keep their defaults and their `has_` flag false.
struct DeviceState {
  Pose pose;  ///< Tool point position (m) and orientation (identity for 3-DOF input).
  Eigen::Vector3d linear_velocity = Eigen::Vector3d::Zero();   ///< m/s, if has_linear_velocity.
  Eigen::Vector3d angular_velocity = Eigen::Vector3d::Zero();  ///< rad/s, world axes.
  bool has_linear_velocity = false;
  bool has_angular_velocity = false;
  std::uint32_t buttons = 0;  ///< Bit i set while button i is held.
  double time = 0.0;          ///< Device clock at the reading (s), non-decreasing.
  bool valid = false;         ///< False when the reading failed; then the rest is stale.
};

/// A haptic device: a pose to read and a wrench to write, once per haptic cycle.
///
/// Threading contract: open(), close() and capabilities() belong to the thread that owns the
/// device and are called while no haptic loop runs; read() and write() are called only from the
/// haptic thread, alternately (read, then write for the same cycle). read() and write() are
/// noexcept, allocate nothing, take no lock that a non-real-time thread may hold for long, and
/// do no I/O beyond talking to the device. The call is virtual: once per cycle, not per point.
///
/// Implementations report failure by returning false, never by throwing in the cycle. Output is
/// raw: devices do not clamp or check what they are given; SafeDevice, the layer every device
/// goes through, does.
class KHZ_HAPTIC_API Device {
 public:
  virtual ~Device();
  Device(const Device&) = delete;
  Device& operator=(const Device&) = delete;

  /// Connects to the device and starts whatever servo it needs. @throws Error / IoError.
  virtual void open() = 0;
  /// Stops output (renders zero) and disconnects. Idempotent.
  virtual void close() noexcept = 0;
  virtual bool is_open() const noexcept = 0;
  /// Valid from construction (after open() for devices that query the hardware).
  virtual const DeviceCapabilities& capabilities() const noexcept = 0;

  /// Reads the current state into `state` (device axes). Returns false and sets state.valid to
  /// false when the device cannot be read (closed, disconnected, communication error).
  virtual bool read(DeviceState& state) noexcept = 0;
  /// Sends a wrench (device axes: N, and N·m about the tool point) to be rendered until the next
  /// write. Returns false if the device did not take it.
  virtual bool write(const Wrench& wrench) noexcept = 0;

 protected:
  Device() = default;
};

}  // namespace khz::haptic
