#pragma once
// The haptic loop (thesis §4.1): a dedicated thread that runs one cycle per period at absolute
// deadlines, optionally with real-time priority and pinned to a CPU, and measures every cycle.

#include <khz/haptic/common.hpp>
#include <khz/haptic/export.hpp>
#include <khz/haptic/loop/loop_statistics.hpp>
#include <khz/haptic/loop/triple_buffer.hpp>

#include <atomic>
#include <cstdint>
#include <functional>
#include <future>
#include <string>
#include <thread>
#include <vector>

namespace khz::haptic {

/// How the loop runs.
struct KHZ_HAPTIC_API LoopOptions {
  /// Cycles per second (> 0, ≤ 100 kHz). Haptic devices want 1 kHz or more.
  double rate_hz = 1000.0;
  /// Ask for SCHED_FIFO at `priority`. Needs CAP_SYS_NICE (or root, or an rtprio limit); when
  /// refused, the loop runs at normal priority and warnings() says so.
  bool realtime_priority = false;
  int priority = 80;  ///< SCHED_FIFO priority, 1–99.
  /// Pin the loop's thread to this CPU (≥ 0), or leave it free (−1). A refused pin is a warning.
  /// While a pinned loop runs, the process's other threads (and the worker threads they start:
  /// precomputations, OpenMP, OpenBLAS) are kept off its CPU, except a thread that has no other
  /// (reduced::worker_threads() counts the CPUs left); when it stops they get the CPU back.
  int cpu = -1;
  /// Cycles between two statistics() snapshots (≥ 1): each costs one pass over the timing
  /// histogram (20,000 bins), so every cycle would be wasteful.
  int statistics_every = 100;
  /// @throws Error naming the first option out of range.
  void validate() const;
};

/// What a cycle is told about itself.
struct CycleClock {
  std::int64_t cycle = 0;  ///< 0, 1, 2, … (skipped periods are not numbered).
  double time = 0.0;       ///< Scheduled start, s since the loop started.
  double period = 0.0;     ///< s.
};

/// Runs `cycle` once per period on its own thread until stop().
///
/// Cycle k is scheduled at t₀ + k·T (absolute deadlines, so lateness never accumulates); the
/// thread sleeps until then (clock_nanosleep, TIMER_ABSTIME on CLOCK_MONOTONIC), runs the
/// cycle, and records how long the work took and how late it woke. A cycle whose work ends
/// after the next scheduled start missed its deadline; the loop then skips the periods already
/// past rather than run cycles back to back (and counts them).
///
/// Threads: start(), stop(), statistics() and warnings() belong to one controlling thread; the
/// cycle runs on the loop's thread and must not block or allocate if the loop is to keep time.
/// Nothing in the loop takes a lock: statistics reach the controlling thread through a triple
/// buffer. A cycle that throws stops the loop; error() then holds the message.
class KHZ_HAPTIC_API HapticLoop {
 public:
  using Cycle = std::function<void(const CycleClock&)>;

  /// @throws Error if the options fail validate().
  explicit HapticLoop(const LoopOptions& options = {});
  /// Stops the loop if it runs.
  ~HapticLoop();
  HapticLoop(const HapticLoop&) = delete;
  HapticLoop& operator=(const HapticLoop&) = delete;

  /// Starts the thread and returns once it has applied (or failed to apply) its priority and
  /// CPU pin; the first cycle starts one period later.
  /// @throws Error if the loop already runs or `cycle` is empty.
  void start(Cycle cycle);
  /// Asks the loop to finish its current cycle and joins the thread. Idempotent.
  void stop() noexcept;
  /// Whether the thread runs cycles (false after stop() or after a cycle threw).
  bool running() const noexcept { return m_running.load(std::memory_order_acquire); }

  /// The newest snapshot of the timing (at most statistics_every cycles old while running; all
  /// cycles after stop()).
  LoopStatistics statistics() noexcept;
  /// What start() could not do (real-time priority, CPU pin), one message each.
  const std::vector<std::string>& warnings() const noexcept { return m_warnings; }
  /// The message of the exception a cycle threw, or empty.
  const std::string& error() const noexcept { return m_error; }

 private:
  void run(std::promise<void>& ready) noexcept;

  LoopOptions m_options;
  Cycle m_cycle;
  std::thread m_thread;
  std::atomic<bool> m_stop{false};
  std::atomic<bool> m_running{false};
  std::vector<std::string> m_warnings;
  std::string m_error;
  LoopTiming m_timing;
  TripleBuffer<LoopStatistics> m_published;
  LoopStatistics m_final;
  bool m_stopped_once = false;
};

}  // namespace khz::haptic
