#pragma once
// Per-cycle timing of the haptic loop: what a haptic application must watch (thesis §4.1: one
// cycle per millisecond, every millisecond).

#include <khz/haptic/export.hpp>

#include <cstdint>
#include <vector>

namespace khz::haptic {

/// A summary of the cycles so far (µs): how long each cycle's work took, and how late cycles
/// started or finished.
struct KHZ_HAPTIC_API LoopStatistics {
  std::int64_t cycles = 0;           ///< Cycles run.
  std::int64_t deadline_misses = 0;  ///< Cycles whose work ended after the next cycle's start.
  std::int64_t skipped_cycles = 0;   ///< Periods dropped to catch up after an overrun.
  double mean_work = 0.0;            ///< Mean work time per cycle (µs).
  double p50_work = 0.0;             ///< Median work time (µs, 1 µs resolution).
  double p99_work = 0.0;             ///< 99th percentile of the work time (µs).
  double max_work = 0.0;             ///< Longest work time (µs).
  double max_start_lateness = 0.0;   ///< Latest wake-up after a cycle's scheduled start (µs).
};

/// Accumulates cycle times without allocating after construction: a histogram of 1 µs bins up
/// to `histogram_microseconds`, longer times in the last bin (their maximum is kept exactly).
class KHZ_HAPTIC_API LoopTiming {
 public:
  explicit LoopTiming(int histogram_microseconds = 20000);

  /// Records one cycle: its work time and how late it started (µs), whether it missed its
  /// deadline, and how many periods were skipped after it. Allocation-free.
  void record(double work_microseconds, double start_lateness_microseconds, bool missed,
              std::int64_t skipped) noexcept;
  /// The summary so far; percentiles cost one pass over the histogram.
  LoopStatistics summary() const noexcept;
  /// Forgets every cycle.
  void clear() noexcept;

 private:
  std::vector<std::int64_t> m_histogram;
  LoopStatistics m_totals;  // counts, maxima and the sum of work times in mean_work
};

}  // namespace khz::haptic
