#pragma once
// A steady press (issue 19's settling target): any scene's device replayed until a moment and
// then held there at rest, and the scene run again that way.

#include <khz/haptic/device/device.hpp>
#include <khz/haptic/world/cycle_metrics.hpp>
#include <khz/scene/prepared_scene.hpp>
#include <khz/scene/run_scene.hpp>

#include <cstdint>
#include <memory>
#include <vector>

namespace khz::run {

/// Wraps a device (owned) and, from the first reading at or after `hold_time` (s, the device's
/// clock), reports the pose and buttons of that reading at rest (zero velocities; a hand holding
/// still lets go of nothing it grasps), the clock as the device gives it. Everything else is the
/// wrapped device's. Faults pass through (a failed read still fails).
class HeldStillDevice final : public haptic::Device {
 public:
  HeldStillDevice(std::unique_ptr<haptic::Device> device, double hold_time);

  void open() override;
  void close() noexcept override { m_device->close(); }
  bool is_open() const noexcept override { return m_device->is_open(); }
  const haptic::DeviceCapabilities& capabilities() const noexcept override {
    return m_device->capabilities();
  }
  bool read(haptic::DeviceState& state) noexcept override;
  bool write(const haptic::Wrench& wrench) noexcept override { return m_device->write(wrench); }

 private:
  std::unique_ptr<haptic::Device> m_device;
  double m_hold_time;
  bool m_held = false;
  haptic::Pose m_pose;
  std::uint32_t m_buttons = 0;
};

/// A steady press and what it showed.
struct SteadyPress {
  double hold_time = 0.0;  ///< s: the cycle of hand 0's largest contact force in the run given.
  scene::HandRows rows;    ///< The pressed run's rows, one list per hand.
  /// Each hand's metrics over the pressed run (haptic::World::metrics()).
  std::vector<haptic::CycleMetricsSummary> metrics;
};

/// Runs `prepared` again with every hand's own device (scene::make_device()) held still
/// (HeldStillDevice) from the cycle of hand 0's largest contact force in `run` (hand 0's rows of
/// an earlier run of the scene), for `seconds` after it.
/// @throws reduced::Error if `run` has no contact, or as scene::make_device() and run_scene().
SteadyPress steady_press(const scene::PreparedScene& prepared,
                         const std::vector<scene::CycleRow>& run, double seconds);

}  // namespace khz::run
