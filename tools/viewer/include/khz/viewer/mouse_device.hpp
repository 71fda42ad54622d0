#pragma once
// The mouse as a manipulandum: a haptic::Device whose position the viewer's drawing thread sets
// from the cursor, read lock-free by the haptic thread.

#include <khz/haptic/device/device.hpp>
#include <khz/haptic/loop/triple_buffer.hpp>

#include <Eigen/Core>

#include <chrono>

namespace khz::viewer {

/// A 3-DOF input device without motors, driven by software: set_position() (any one thread,
/// e.g. the one that handles the mouse) publishes a position, read() (the haptic thread) returns
/// the newest one. The hand-off is a haptic::TripleBuffer, so neither thread ever waits.
/// write() takes the wrench and renders nothing (0 output DOF); the last one is kept for
/// display. Behind a haptic::SafeDevice that wrench is always zero: the safety layer drops the
/// force of a device without force output.
class MouseDevice final : public haptic::Device {
 public:
  /// Capabilities: "mouse", 3 input DOF (position; read() reports the identity orientation),
  /// 0 output DOF, the workspace box ±`reach` around the device origin, `nominal_rate`. The
  /// force and stiffness limits (10 N, 2000 N/m) only satisfy DeviceCapabilities::validate():
  /// nothing is rendered.
  /// @param nominal_rate the haptic loop's rate (Hz), > 0.
  /// @param reach half the workspace box's side (m), > 0.
  /// @throws haptic::Error if the capabilities fail validate() (a rate or reach that is not
  ///         finite and > 0).
  explicit MouseDevice(double nominal_rate = 1000.0, double reach = 1.0);

  void open() override;
  void close() noexcept override { m_open = false; }
  bool is_open() const noexcept override { return m_open; }
  const haptic::DeviceCapabilities& capabilities() const noexcept override {
    return m_capabilities;
  }

  /// The newest published position (the device origin before any), the identity orientation,
  /// no velocities, no buttons, the steady clock's seconds since open(). False (and
  /// state.valid false) while closed. Wait-free; the haptic thread only.
  bool read(haptic::DeviceState& state) noexcept override;
  /// Keeps `wrench` for last_wrench() and renders nothing. False while closed. Wait-free; the
  /// haptic thread only.
  bool write(const haptic::Wrench& wrench) noexcept override;

  /// Publishes the tool point's position (m, device axes), clamped to the workspace box;
  /// non-finite coordinates are ignored. Wait-free; from one thread at a time (the mouse's).
  void set_position(const Eigen::Vector3d& position) noexcept;
  /// The wrench of the newest write() (zero before any). Wait-free; from one thread at a time
  /// (the one that displays it).
  const haptic::Wrench& last_wrench() noexcept;

 private:
  haptic::DeviceCapabilities m_capabilities;
  bool m_open = false;
  std::chrono::steady_clock::time_point m_opened;
  haptic::TripleBuffer<Eigen::Vector3d> m_position{Eigen::Vector3d::Zero()};
  haptic::TripleBuffer<haptic::Wrench> m_wrench;
};

}  // namespace khz::viewer
