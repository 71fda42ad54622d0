#include "scene_session.hpp"

#include "scene_preparation.hpp"

#include <khz/render/png_file.hpp>
#include <khz/run/device_choice.hpp>
#include <khz/run/frame_renderer.hpp>
#include <khz/run/frame_series.hpp>
#include <khz/run/free_bodies.hpp>
#include <khz/run/run_realtime.hpp>
#include <khz/scene/make_device.hpp>
#include <khz/scene/read_scene.hpp>
#include <khz/scene/run_scene.hpp>
#include <khz/scene/run_summary.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <optional>
#include <utility>

namespace khz::tool {
namespace {

std::filesystem::path frame_file(const std::filesystem::path& directory, int frame) {
  char name[32];
  std::snprintf(name, sizeof name, "frame_%05d.png", frame);
  return directory / name;
}

run::DeviceChoice device_choice(const RunRequest& request) {
  run::DeviceChoice choice;
  choice.trajectory = request.trajectory;
  choice.operator_script = request.operator_script;
  choice.hardware = request.device;
  return choice;
}

/// A run that produced non-finite values fails the command (after its logs are written).
void require_finite(const std::vector<scene::RunSummary>& summaries) {
  for (const scene::RunSummary& summary : summaries) {
    if (!summary.finite) throw reduced::Error("the run produced non-finite forces or poses");
  }
}

/// The files, comma-separated.
std::string files_text(const std::vector<std::filesystem::path>& files) {
  std::string text;
  for (const std::filesystem::path& file : files)
    text += (text.empty() ? "" : ", ") + file.string();
  return text;
}

}  // namespace

void add_run_options(CLI::App& command, RunRequest& request) {
  command.add_option("scene", request.scene, "Scene file (JSON, docs/SCENES.md)")
      ->required()
      ->check(CLI::ExistingFile);
  CLI::Option* trajectory =
      command
          .add_option("--trajectory", request.trajectory,
                      "Replay this trajectory CSV instead of the scene's device")
          ->check(CLI::ExistingFile);
  CLI::Option* script =
      command
          .add_option("--operator", request.operator_script,
                      "Drive the scene with this device file instead (JSON like the scene's "
                      "\"device\", e.g. an operator's keyframes)")
          ->check(CLI::ExistingFile);
  CLI::Option* device = command.add_option(
      "--device", request.device, "Use this hardware device backend (none is built into khz)");
  trajectory->excludes(script)->excludes(device);
  script->excludes(device);
  command.add_option("--out", request.out, "Output directory (default: khz-run/<scene name>)");
  command.add_option("--cache", request.cache,
                     "Product cache directory (default: $XDG_CACHE_HOME/kilohertz, else "
                     "~/.cache/kilohertz)");
  command
      .add_option("--duration", request.duration,
                  "Simulated seconds (default: loop.duration, or the trajectory's or operator's "
                  "length)")
      ->check(CLI::NonNegativeNumber);
  command.add_option("--frames", request.frame_rate, "PNG frames per simulated second; 0: none")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  command.add_option("--width", request.width, "Frame width (pixels)")
      ->capture_default_str()
      ->check(CLI::Range(16, 8192));
  command.add_option("--height", request.height, "Frame height (pixels)")
      ->capture_default_str()
      ->check(CLI::Range(16, 8192));
  command.add_flag("--realtime", request.realtime,
                   "Run on the real-time haptic loop (loop.rate_hz, realtime_priority, cpu) "
                   "instead of in simulated time; reports deadline misses; no frames. A hardware "
                   "--device always runs so");
  command.add_flag("--paraview", request.paraview,
                   "Also write each frame as a ParaView time series (<out>/paraview/run.pvd: "
                   "surfaces, pointshell points with their state, the force)");
}

SceneSession::SceneSession(const RunRequest& request)
    : m_request(request),
      m_out(request.out.empty()
                ? std::filesystem::path("khz-run") / std::filesystem::path(request.scene).stem()
                : std::filesystem::path(request.out)) {
  const scene::SceneDescription description = scene::read_scene(request.scene);
  m_devices = run::choose_devices(description, device_choice(request));
  // A device khz cannot make (a hardware backend: none is built in) is refused before a
  // possibly long preparation.
  for (const scene::DeviceDescription& device : m_devices) {
    if (device.type == scene::DeviceType::hardware) scene::make_device(device);  // throws
  }
  m_prepared =
      prepare_with_progress(description, cache_directory(request.cache, request.scene), std::cout);
  m_runtime = std::make_unique<scene::SceneRuntime>(m_prepared, m_devices);
}

SceneSession::~SceneSession() = default;

RunResult SceneSession::run(bool record_states) {
  const scene::SceneDescription& description = m_prepared.description;
  if (m_request.realtime || !m_request.device.empty()) {
    if (record_states) throw reduced::Error("a real-time run keeps no states to report on");
    return run_realtime();
  }
  const std::filesystem::path frames = m_out / "frames";
  std::filesystem::create_directories(m_out);
  std::filesystem::remove_all(frames);
  std::optional<run::FrameRenderer> renderer;
  std::optional<run::FrameSeries> series;
  int frame_every = 0;
  RunResult result;
  if (m_request.frame_rate > 0.0) {
    std::filesystem::create_directories(frames);
    run::FrameOptions options;
    options.width = m_request.width;
    options.height = m_request.height;
    renderer.emplace(*m_runtime, options);
    frame_every =
        std::max(1, static_cast<int>(std::lround(description.loop.rate_hz / m_request.frame_rate)));
    if (m_request.paraview) {
      series.emplace(*m_runtime, m_out / "paraview");
      result.paraview = series->collection_file();
    }
  }

  const InterruptRequest interrupt;
  scene::RunOptions options;
  options.duration = m_request.duration;
  options.frame_every = record_states || frame_every == 0 ? 1 : frame_every;
  options.on_frame = [&](int cycle, scene::SceneRuntime& runtime) {
    if (record_states) result.states.push_back(scene::record_state(runtime));
    if (renderer && cycle % frame_every == 0) {
      const run::FrameContent frame = run::capture_frame(runtime);
      result.frames.push_back(frame_file(frames, static_cast<int>(result.frames.size())));
      render::write_png(renderer->render(frame), result.frames.back());
      if (series) series->write(frame);
    }
    return !interrupt.requested();
  };

  std::cout << "running " << m_request.scene << "\n";
  const auto start = std::chrono::steady_clock::now();
  result.rows = scene::run_scene(*m_runtime, options);
  const double wall =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  result.interrupted = interrupt.requested();
  const std::vector<scene::RunSummary> summaries = log_rows(result);
  run::print_free_bodies(std::cout, run::free_body_states(*m_runtime));
  std::cout << "wall time: " << wall << " s" << (result.interrupted ? " (interrupted)" : "")
            << "\nwrote " << files_text(result.csv);
  if (!result.frames.empty()) {
    std::cout << " and " << result.frames.size() << " frames in " << frames.string();
  }
  if (!result.paraview.empty()) std::cout << "\nwrote " << result.paraview.string();
  std::cout << "\n";
  require_finite(summaries);
  return result;
}

RunResult SceneSession::run_realtime() {
  std::filesystem::create_directories(m_out);
  const InterruptRequest interrupt;
  std::cout << "running " << m_request.scene << " in real time at "
            << m_prepared.description.loop.rate_hz << " Hz\n";
  run::RealtimeRun realtime = run::run_scene_realtime(*m_runtime, m_request.duration,
                                                      [&] { return interrupt.requested(); });
  for (const std::string& warning : realtime.warnings) std::cout << "loop: " << warning << "\n";
  RunResult result;
  result.rows = std::move(realtime.rows);
  result.interrupted = interrupt.requested();
  const std::vector<scene::RunSummary> summaries = log_rows(result);
  run::print_free_bodies(std::cout, run::free_body_states(*m_runtime));
  const haptic::LoopStatistics& loop = realtime.loop;
  std::cout << "loop: " << loop.cycles << " cycles, " << loop.deadline_misses
            << " deadline misses, " << loop.skipped_cycles << " periods skipped; work mean "
            << loop.mean_work << " us, p99 " << loop.p99_work << " us, max " << loop.max_work
            << " us; latest wake-up " << loop.max_start_lateness << " us late\n"
            << "wrote " << files_text(result.csv) << "\n";
  require_finite(summaries);
  return result;
}

std::vector<scene::RunSummary> SceneSession::log_rows(RunResult& result) const {
  std::vector<scene::RunSummary> summaries;
  const double period = 1.0 / m_prepared.description.loop.rate_hz;
  const std::size_t hands = result.rows.size();
  for (std::size_t h = 0; h < hands; ++h) {
    result.csv.push_back(h == 0 ? m_out / "cycles.csv"
                                : m_out / ("cycles_hand" + std::to_string(h) + ".csv"));
    scene::write_cycle_csv(result.rows[h], result.csv.back());
    if (hands > 1) {
      const scene::HapticDescription& hand = m_prepared.description.haptic[h];
      std::cout << "hand " << h << " (" << hand.object << "):\n";
    }
    summaries.push_back(scene::summarize(result.rows[h], period));
    summaries.back().metrics = m_runtime->world().metrics(static_cast<int>(h));
    scene::print_summary(std::cout, summaries.back());
  }
  return summaries;
}

}  // namespace khz::tool
