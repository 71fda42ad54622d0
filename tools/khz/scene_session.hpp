#pragma once
// What `khz run` and `khz report` share: their options, and a scene read, prepared and run in
// simulated time with its per-cycle CSV and PNG frames written.

#include <khz/scene/contact_sweep.hpp>
#include <khz/scene/cycle_log.hpp>
#include <khz/scene/run_scene.hpp>
#include <khz/scene/run_summary.hpp>
#include <khz/scene/scene_runtime.hpp>

#include <CLI/CLI.hpp>

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace khz::tool {

/// The command line of a scene run.
struct RunRequest {
  std::string scene, cache, out, trajectory, operator_script, device;
  double duration = 0.0;     ///< 0: the scene's.
  double frame_rate = 10.0;  ///< PNG frames per simulated second; 0: none.
  int width = 800, height = 600;
  bool paraview = false;  ///< Also write the frames as a ParaView time series.
  bool realtime = false;  ///< Run on the real-time loop (implied by a hardware device).
};

/// Registers the options of RunRequest on `command` (scene, --trajectory | --operator |
/// --device, --out, --cache, --duration, --frames, --width, --height, --paraview, --realtime).
void add_run_options(CLI::App& command, RunRequest& request);

/// What a run wrote and kept.
struct RunResult {
  scene::HandRows rows;  ///< Per hand, per cycle.
  /// Per hand: <out>/cycles.csv for the first, <out>/cycles_hand<h>.csv for hand h ≥ 1.
  std::vector<std::filesystem::path> csv;
  std::vector<std::filesystem::path> frames;  ///< <out>/frames/frame_NNNNN.png
  std::filesystem::path paraview;             ///< <out>/paraview/run.pvd, if written
  std::vector<scene::RecordedState> states;   ///< Every cycle's, when asked for.
  bool interrupted = false;                   ///< Ctrl-C stopped it early.
};

/// A scene read, prepared (progress bars on stderr, summary on stdout) and made runnable.
class SceneSession {
 public:
  /// @throws what reading, preparing or scene::SceneRuntime throw.
  explicit SceneSession(const RunRequest& request);
  ~SceneSession();

  /// The output directory: --out, or khz-run/<scene file stem>.
  const std::filesystem::path& out() const noexcept { return m_out; }
  scene::SceneRuntime& runtime() noexcept { return *m_runtime; }
  /// The prepared scene the runtime runs (scene::stability_map() varies its description).
  scene::PreparedScene& prepared() noexcept { return m_prepared; }
  /// The devices the runtime runs with, one per hand (the scene's, or the command line's).
  const std::vector<scene::DeviceDescription>& devices() const noexcept { return m_devices; }

  /// Runs the scene (scene::run_scene(); run::run_scene_realtime() with --realtime or a hardware
  /// device, without frames), writes each hand's cycle CSV and the frames, prints the summary. With
  /// `record_states`, keeps every cycle's state for scene::sweep_contact() (simulated time only).
  /// @throws reduced::Error if the run produced non-finite values (after writing the CSV).
  RunResult run(bool record_states);

 private:
  RunResult run_realtime();
  /// Writes each hand's rows to its CSV file (setting result.csv) and prints their summaries.
  /// @returns the summaries, one per hand.
  std::vector<scene::RunSummary> log_rows(RunResult& result) const;

  RunRequest m_request;
  std::filesystem::path m_out;
  scene::PreparedScene m_prepared;
  std::vector<scene::DeviceDescription> m_devices;
  std::unique_ptr<scene::SceneRuntime> m_runtime;
};

}  // namespace khz::tool
