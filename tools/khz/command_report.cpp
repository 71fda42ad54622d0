#include "commands.hpp"
#include "progress_bar.hpp"
#include "scene_preparation.hpp"
#include "scene_session.hpp"

#include <khz/run/run_report.hpp>

#include <unistd.h>

#include <algorithm>
#include <iostream>
#include <memory>
#include <utility>

namespace khz::tool {
namespace {

/// At most `count` of the frames, evenly spaced, relative to `directory`.
std::vector<std::filesystem::path> some_frames(const std::vector<std::filesystem::path>& frames,
                                               const std::filesystem::path& directory,
                                               std::size_t count) {
  std::vector<std::filesystem::path> chosen;
  for (std::size_t k = 0; k < std::min(count, frames.size()); ++k) {
    const std::size_t i = count == 1 ? 0 : k * (frames.size() - 1) / (count - 1);
    chosen.push_back(std::filesystem::relative(frames[i], directory));
  }
  return chosen;
}

void report(const RunRequest& request, bool stability) {
  SceneSession session(request);
  RunResult result = session.run(true);
  scene::SceneRuntime& runtime = session.runtime();
  // Where the run left the free objects, before the sweep moves them.
  std::vector<run::FreeBodyState> free_bodies = run::free_body_states(runtime);
  const std::vector<scene::SweepSetting> settings =
      scene::default_sweep(runtime.description().contact, scene::tree_levels(runtime.prepared()));
  std::cout << "speed against error: " << settings.size() << " settings over the states in "
            << "contact among the " << result.states.size() << " recorded (at most "
            << scene::default_sweep_states << ", evenly spaced)\n";
  ProgressBar bar(std::cerr, ::isatty(STDERR_FILENO) == 1);
  const InterruptRequest interrupt;
  const std::vector<scene::SweepResult> sweep =
      scene::sweep_contact(runtime, result.states, settings, scene::default_sweep_states,
                           [&](const reduced::Progress& progress) {
                             bar.update("replaying", progress);
                             return !interrupt.requested();
                           });
  bar.clear();
  std::cout << "replayed " << sweep.front().states << " states in contact under each setting\n";
  std::vector<scene::StabilityPoint> stability_points;
  if (stability) {
    const std::vector<scene::StabilitySetting> runs =
        scene::default_stability_settings(session.prepared().description);
    std::cout << "stability map: the scene run " << runs.size()
              << " times, one parameter changed at a time (--no-stability skips it)\n";
    stability_points =
        scene::stability_map(session.prepared(), runs, request.duration, session.devices(),
                             [&](const reduced::Progress& progress) {
                               bar.update("stability map", progress);
                               return !interrupt.requested();
                             });
    bar.clear();
    for (const scene::StabilityPoint& point : stability_points) {
      std::cout << "  " << point.setting.name() << ": "
                << (!point.refused.empty() ? "refused (" + point.refused + ")"
                    : point.smooth()       ? "stable and smooth"
                    : point.stable()       ? "stable, not smooth"
                                           : "UNSTABLE")
                << "\n";
    }
  }
  run::ReportInput input;
  input.scene = request.scene;
  input.description = runtime.description().description;
  input.rate_hz = runtime.description().loop.rate_hz;
  // The report's plots and tables follow the first hand; the sweep covers every hand.
  input.rows = std::move(result.rows.front());
  input.metrics = runtime.world().metrics(0);
  input.sweep = sweep;
  input.stability = std::move(stability_points);
  input.frames = some_frames(result.frames, session.out(), 4);
  input.free_bodies = std::move(free_bodies);
  const run::ReportFiles files = run::write_report(session.out(), input);
  std::cout << "wrote " << files.markdown.string() << "\n";
}

}  // namespace

void add_report_command(CLI::App& app) {
  auto request = std::make_shared<RunRequest>();
  CLI::App* command = app.add_subcommand(
      "report",
      "Run a scene as `khz run` does, then replay its states in contact at every level of "
      "detail and under time budgets, run it again with one parameter changed at a time "
      "(the stability map), and write report.md with PNG plots: force and torque over time, "
      "per-cycle cost, the contact query's speed against error, and stability");
  add_run_options(*command, *request);
  auto no_stability = std::make_shared<bool>(false);
  command->add_flag("--no-stability", *no_stability,
                    "Skip the stability map (it runs the scene about a dozen times)");
  command->callback([request, no_stability] { report(*request, !*no_stability); });
}

}  // namespace khz::tool
