#include <khz/scene/run_scene.hpp>

#include <chrono>
#include <cmath>

namespace khz::scene {
namespace {

/// Closes the devices however the run ends.
struct OpenDevices {
  explicit OpenDevices(SceneRuntime& opened) : runtime(opened) { runtime.open_devices(); }
  ~OpenDevices() { runtime.close_devices(); }
  OpenDevices(const OpenDevices&) = delete;
  OpenDevices& operator=(const OpenDevices&) = delete;
  SceneRuntime& runtime;
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

HandRows run_scene(SceneRuntime& runtime, const RunOptions& options) {
  const std::size_t cycles = run_cycles(runtime, options.duration);
  if (options.frame_every < 1) throw reduced::Error("RunOptions::frame_every must be >= 1");
  const double period = 1.0 / runtime.description().loop.rate_hz;
  HandRows rows(static_cast<std::size_t>(runtime.hand_count()));
  for (std::vector<CycleRow>& hand : rows) hand.reserve(cycles);

  OpenDevices open(runtime);
  haptic::World& world = runtime.world();
  world.reset_metrics();  // the run's own figures
  using Clock = std::chrono::steady_clock;
  for (std::size_t i = 0; i < cycles; ++i) {
    const double now = static_cast<double>(i) * period;
    const Clock::time_point start = Clock::now();
    const std::span<const haptic::CycleRecord> records =
        world.cycle(now, now + period, [now] { return now; });
    const double us = std::chrono::duration<double, std::micro>(Clock::now() - start).count();
    for (std::size_t h = 0; h < records.size(); ++h) {
      rows[h].push_back(CycleRow::from(records[h], us));
    }
    if (options.on_frame && i % static_cast<std::size_t>(options.frame_every) == 0 &&
        !options.on_frame(static_cast<int>(i), runtime)) {
      break;
    }
  }
  return rows;
}

}  // namespace khz::scene
