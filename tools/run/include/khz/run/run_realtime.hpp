#pragma once
// Running a scene in real time: the haptic cycle on libhaptic's HapticLoop thread at the loop's
// rate, priority and CPU, as a hardware device needs it.

#include <khz/haptic/loop/loop_statistics.hpp>
#include <khz/scene/run_scene.hpp>
#include <khz/scene/scene_runtime.hpp>

#include <functional>
#include <string>
#include <vector>

namespace khz::run {

/// What a real-time run did.
struct RealtimeRun {
  scene::HandRows rows;               ///< Per hand, one per cycle run, in order.
  haptic::LoopStatistics loop;        ///< The loop's timing: work, lateness, deadline misses.
  std::vector<std::string> warnings;  ///< The loop's (e.g. real-time priority refused).
};

/// Opens the devices and runs the scene's World on a haptic::HapticLoop (the scene's
/// LoopOptions: rate, SCHED_FIFO priority, CPU) for `duration` seconds of wall-clock time (0:
/// SceneRuntime::natural_duration()), or until `stop_requested` (polled every 10 ms by the
/// calling thread, never the loop's; may be empty) returns true; then stops the loop and closes the
/// devices. The cycle records its row into storage reserved beforehand, so the loop thread
/// allocates nothing; the calling thread sleeps until the end. Each cycle's time is its scheduled
/// start on the loop's clock, and the watchdog gets that start plus the cycle's measured work.
/// The World's metrics are reset when the devices open, as in run_scene().
/// @throws reduced::Error if there is no duration, the loop stopped on an error, or as the
///         device's open().
RealtimeRun run_scene_realtime(scene::SceneRuntime& runtime, double duration,
                               const std::function<bool()>& stop_requested = {});

}  // namespace khz::run
