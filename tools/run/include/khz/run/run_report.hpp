#pragma once
// The report `khz report` writes: Markdown with the run's figures, its smoothness, steadiness
// and passivity, the contact query's speed against error and the stability map, and PNG plots of
// force, torque, force jumps, the passivity observer, per-cycle cost, speed against error and
// stability.

#include <khz/run/free_bodies.hpp>
#include <khz/scene/contact_sweep.hpp>
#include <khz/scene/cycle_log.hpp>
#include <khz/scene/run_summary.hpp>
#include <khz/scene/stability_map.hpp>

#include <filesystem>
#include <string>
#include <vector>

namespace khz::run {

/// What a report is made of.
struct ReportInput {
  std::string scene;        ///< The scene file as named.
  std::string description;  ///< The scene's description text.
  double rate_hz = 1000.0;  ///< The loop's rate.
  std::vector<scene::CycleRow> rows;
  /// The runtime's figures for the same hand (haptic::World::metrics() after the run).
  haptic::CycleMetricsSummary metrics;
  std::vector<scene::SweepResult>
      sweep;  ///< First entry: the reference (may be empty: no contact).
  /// The stability map (may be empty: not run); the first point is the scene as given.
  std::vector<scene::StabilityPoint> stability;
  /// Frame pictures to show, relative to the report's directory.
  std::vector<std::filesystem::path> frames;
  /// Where the run left the scene's free objects (empty: none).
  std::vector<FreeBodyState> free_bodies;
};

/// The files write_report() makes, in `directory`.
struct ReportFiles {
  std::filesystem::path markdown;     ///< report.md
  std::filesystem::path force_plot;   ///< force.png: |F| contact and rendered, over time.
  std::filesystem::path torque_plot;  ///< torque.png: |T| over time.
  std::filesystem::path cost_plot;    ///< cost.png: µs per cycle and per query over time.
  /// jumps.png: |F_k − F_{k−1}|, contact and rendered, over time (chatter).
  std::filesystem::path jump_plot;
  /// energy.png: the passivity observer over time (below zero: energy given to the hand).
  std::filesystem::path energy_plot;
  std::filesystem::path speed_plot;  ///< speed_vs_error.png (only with a sweep).
  /// stability.png: contact-force jump p99 against each parameter's factor (only with a map).
  std::filesystem::path stability_plot;
};

/// Writes report.md and the plots into `directory` (created if needed).
/// @throws reduced::IoError naming a file that cannot be written.
ReportFiles write_report(const std::filesystem::path& directory, const ReportInput& input);

}  // namespace khz::run
