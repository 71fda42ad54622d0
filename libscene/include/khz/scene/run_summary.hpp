#pragma once
// The figures of a run that `khz run` prints and `khz report` tabulates.

#include <khz/haptic/world/cycle_metrics.hpp>
#include <khz/scene/cycle_log.hpp>
#include <khz/scene/export.hpp>

#include <cstdint>
#include <iosfwd>
#include <vector>

namespace khz::scene {

/// Mean and quantiles of a per-cycle quantity (exact, from all the values).
using Spread = haptic::Quantiles;

/// Mean, median, 99th percentile (nearest rank), maximum and count; all zero for no values.
KHZ_SCENE_API Spread spread(std::vector<double> values);

/// A run in figures.
struct KHZ_SCENE_API RunSummary {
  std::int64_t cycles = 0;
  double duration = 0.0;               ///< Simulated s: the last cycle's time plus one period.
  Spread cycle_us;                     ///< Whole cycle, all cycles.
  Spread query_us;                     ///< Contact queries, all cycles.
  Spread query_us_in_contact;          ///< Contact queries, cycles with points in contact.
  std::int64_t cycles_in_contact = 0;  ///< Cycles with at least one point in contact.
  std::int64_t failed_cycles = 0;      ///< Rows with ok false.
  std::int64_t incomplete_cycles = 0;  ///< Rows where degradation cut a level.
  std::int64_t max_contacts = 0;       ///< Points in contact, most in one cycle.
  std::int64_t contact_points = 0;     ///< Points in contact, summed over the cycles.
  std::int64_t sliding_points = 0;     ///< Of those, the points whose friction slid.
  std::int64_t max_nodes = 0;          ///< Nodes traversed, most in one cycle.
  int deepest_level = -1;              ///< Deepest level any cycle rendered.
  double max_force = 0.0;              ///< Largest |contact force| (N).
  double max_torque = 0.0;             ///< Largest |contact torque| (N·m).
  double max_rendered_force = 0.0;     ///< Largest |rendered force| (N).
  bool finite = true;                  ///< Every force, torque and pose is finite.
  /// The runtime's smoothness, jitter, residual, penetration and energy figures of the hand
  /// (haptic::World::metrics(), set by the caller: rows do not carry them all).
  haptic::CycleMetricsSummary metrics;
};

/// The summary of a run's rows (empty rows give the defaults); `period` is 1 / rate (s).
KHZ_SCENE_API RunSummary summarize(const std::vector<CycleRow>& rows, double period);

/// Prints the summary as a few aligned lines (what `khz run` ends with), the metrics included.
KHZ_SCENE_API void print_summary(std::ostream& out, const RunSummary& summary);

/// 100 · value / peak (%), 0 when the peak is 0.
KHZ_SCENE_API double percent_of(double value, double peak);

/// Prints the runtime's metrics as a few lines (part of print_summary()).
KHZ_SCENE_API void print_metrics(std::ostream& out, const haptic::CycleMetricsSummary& metrics);

}  // namespace khz::scene
