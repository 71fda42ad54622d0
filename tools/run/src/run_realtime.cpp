#include <khz/haptic/loop/haptic_loop.hpp>
#include <khz/run/run_realtime.hpp>
#include <khz/scene/run_scene.hpp>

#include <atomic>
#include <chrono>
#include <thread>

namespace khz::run {

RealtimeRun run_scene_realtime(scene::SceneRuntime& runtime, double duration,
                               const std::function<bool()>& stop_requested) {
  const std::size_t cycles = scene::run_cycles(runtime, duration);
  const haptic::LoopOptions& options = runtime.description().loop;
  RealtimeRun run;
  run.rows.resize(static_cast<std::size_t>(runtime.hand_count()));
  for (std::vector<scene::CycleRow>& hand : run.rows) hand.reserve(cycles);
  std::atomic<bool> done{false};

  haptic::HapticLoop loop(options);
  runtime.open_devices();
  haptic::World& world = runtime.world();
  world.reset_metrics();  // the run's own figures
  using Clock = std::chrono::steady_clock;
  loop.start([&](const haptic::CycleClock& clock) {
    if (run.rows.front().size() == cycles) {
      done.store(true, std::memory_order_release);
      return;
    }
    const Clock::time_point start = Clock::now();
    const auto elapsed = [&] {
      return std::chrono::duration<double>(Clock::now() - start).count();
    };
    const std::span<const haptic::CycleRecord> records =
        world.cycle(clock.time, clock.time + clock.period, [&] { return clock.time + elapsed(); });
    const double us = 1e6 * elapsed();
    for (std::size_t h = 0; h < records.size(); ++h) {
      run.rows[h].push_back(scene::CycleRow::from(records[h], us));
    }
  });
  while (!done.load(std::memory_order_acquire) && !(stop_requested && stop_requested()) &&
         loop.running()) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  loop.stop();
  runtime.close_devices();
  run.loop = loop.statistics();
  run.warnings = loop.warnings();
  if (!loop.error().empty()) throw reduced::Error("the haptic loop stopped: " + loop.error());
  return run;
}

}  // namespace khz::run
