#pragma once
// Running a scene in simulated time: the haptic cycle at the loop's period, as fast as the
// machine goes, each cycle's cost measured and logged (what `khz run` does).

#include <khz/scene/cycle_log.hpp>
#include <khz/scene/export.hpp>
#include <khz/scene/scene_runtime.hpp>

#include <cstddef>
#include <functional>
#include <vector>

namespace khz::scene {

/// Options of run_scene().
struct KHZ_SCENE_API RunOptions {
  /// Simulated seconds to run, > 0; 0 takes SceneRuntime::natural_duration().
  double duration = 0.0;
  /// Called between cycles — outside the timed part — after every `frame_every`-th cycle
  /// (cycle 0 first) with the cycle's index: render, write files, report progress. Return false
  /// to stop the run early.
  std::function<bool(int cycle, SceneRuntime& runtime)> on_frame;
  /// ≥ 1; cycles between on_frame calls.
  int frame_every = 33;
};

/// The cycles a run of `duration` seconds takes (0: SceneRuntime::natural_duration()) at the
/// scene's loop rate: ⌈duration · rate_hz⌉. What run_scene() and run_scene_realtime() run.
/// @throws reduced::Error if there is no duration (null and hardware devices play no
///         recording: set loop.duration, or khz run --duration).
KHZ_SCENE_API std::size_t run_cycles(const SceneRuntime& runtime, double duration);

/// The rows of a run, one list per hand: rows[h][i] is hand h's row of cycle i.
using HandRows = std::vector<std::vector<CycleRow>>;

/// Opens the devices and runs ⌈duration · rate_hz⌉ cycles of the World at simulated times
/// t = i / rate_hz. Each cycle's cost is measured on the steady clock, but the device's
/// watchdog sees the simulated clock (a cycle takes no simulated time), so the run is
/// reproducible: the same scene and inputs give the same rows on every run of a build, whatever
/// the machine's speed; only the µs columns differ (a build for another CPU agrees to
/// round-off). The exception is degradation by time budget
/// (contact.degradation.mode time_budget), whose level of detail follows the measured cost.
/// The devices are closed at the end (also on throw).
/// The World's metrics are reset when the devices open: afterwards world().metrics(h) is
/// hand h's figures over this run.
/// @returns one row per hand and cycle (each hand's cycle_us is the whole cycle's).
/// @throws reduced::Error if the duration is 0 and the device gives none (null and hardware
///         devices: set loop.duration), or as the device's open().
KHZ_SCENE_API HandRows run_scene(SceneRuntime& runtime, const RunOptions& options = {});

}  // namespace khz::scene
