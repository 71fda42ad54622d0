#include <khz/run/run_scene.hpp>

#include <chrono>
#include <cmath>

namespace khz::run {
namespace {

/// Closes the device however the run ends.
struct OpenDevice {
  explicit OpenDevice(haptic::SafeDevice& opened) : device(opened) { device.open(); }
  ~OpenDevice() { device.close(); }
  OpenDevice(const OpenDevice&) = delete;
  OpenDevice& operator=(const OpenDevice&) = delete;
  haptic::SafeDevice& device;
};

}  // namespace

std::size_t run_cycles(const SceneRuntime& runtime, double duration) {
  const double seconds = duration > 0.0 ? duration : runtime.natural_duration();
  if (!(seconds > 0.0) || !std::isfinite(seconds)) {
    throw reduced::Error(
        "the run has no duration: this device plays no recording, so give one (loop.duration "
        "in the scene, or khz run --duration)");
  }
  return static_cast<std::size_t>(std::ceil(seconds * runtime.description().loop.rate_hz - 1e-9));
}

std::vector<CycleRow> run_scene(SceneRuntime& runtime, const RunOptions& options) {
  const std::size_t cycles = run_cycles(runtime, options.duration);
  if (options.frame_every < 1) throw reduced::Error("RunOptions::frame_every must be >= 1");
  const double period = 1.0 / runtime.description().loop.rate_hz;
  std::vector<CycleRow> rows;
  rows.reserve(cycles);

  OpenDevice open(runtime.device());
  haptic::HapticCycle& cycle = runtime.cycle();
  using Clock = std::chrono::steady_clock;
  for (std::size_t i = 0; i < cycles; ++i) {
    const double now = static_cast<double>(i) * period;
    const Clock::time_point start = Clock::now();
    const haptic::CycleRecord& record = cycle.run(now, now + period, [now] { return now; });
    const double us = std::chrono::duration<double, std::micro>(Clock::now() - start).count();
    rows.push_back(CycleRow::from(record, us));
    if (options.on_frame && i % static_cast<std::size_t>(options.frame_every) == 0 &&
        !options.on_frame(static_cast<int>(i), runtime)) {
      break;
    }
  }
  return rows;
}

}  // namespace khz::run
