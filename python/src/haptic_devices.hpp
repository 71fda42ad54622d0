#pragma once
// A haptic::Device written in Python: the trampoline the Python class kilohertz.haptic.Device
// stands on, shared by the bindings of the devices and of the scene runtime that runs them.

#include <khz/haptic/device/device.hpp>

#include <pybind11/pybind11.h>

#include <atomic>
#include <optional>

namespace khz::python {

namespace py = pybind11;

/// The C++ side of a Python subclass of kilohertz.haptic.Device. Each call takes the GIL, calls
/// the subclass's method and converts the result: read() -> DeviceState or None (None: the read
/// failed), write(force, torque) -> bool or None (None: taken). An exception raised by read() or
/// write() counts as a failed call; the first one is kept (failed() turns true) for the loop to
/// stop and raise it once the devices are closed (take_error()).
class PythonDevice : public haptic::Device {
 public:
  /// @throws Error if the capabilities are invalid (DeviceCapabilities::validate()).
  explicit PythonDevice(const haptic::DeviceCapabilities& capabilities);

  void open() override;
  void close() noexcept override;
  bool is_open() const noexcept override { return m_open; }
  const haptic::DeviceCapabilities& capabilities() const noexcept override {
    return m_capabilities;
  }
  bool read(haptic::DeviceState& state) noexcept override;
  bool write(const haptic::Wrench& wrench) noexcept override;

  /// Whether read() or write() raised since the last take_error(); readable without the GIL.
  bool failed() const noexcept { return m_failed.load(std::memory_order_relaxed); }
  /// Raises (as a C++ py::error_already_set) the first exception read() or write() raised, and
  /// forgets it; does nothing if none did. Call with the GIL held.
  void raise_error();

 private:
  /// Keeps the exception being handled, if it is the first.
  void keep_error(py::error_already_set& error) noexcept;

  haptic::DeviceCapabilities m_capabilities;
  bool m_open = false;
  std::atomic<bool> m_failed{false};
  std::optional<py::error_already_set> m_error;
};

}  // namespace khz::python
