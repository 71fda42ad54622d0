#include <khz/haptic/loop/command_queue.hpp>
#include <khz/haptic/loop/haptic_loop.hpp>
#include <khz/haptic/loop/loop_statistics.hpp>
#include <khz/haptic/loop/triple_buffer.hpp>
#include <khz/reduced/worker_threads.hpp>
#include <khz/test/threads_that_ran.hpp>

#include <gtest/gtest.h>

#include <sched.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <thread>
#include <vector>

namespace khz::haptic {
namespace {

/// A value a torn copy would betray: every entry equal.
struct Stamp {
  std::array<std::int64_t, 16> entries{};
  bool consistent() const {
    return std::all_of(entries.begin(), entries.end(),
                       [&](std::int64_t e) { return e == entries[0]; });
  }
};

TEST(TripleBuffer, ReaderSeesWholeValuesInOrderWhileTheWriterRuns) {
  TripleBuffer<Stamp> buffer;
  constexpr std::int64_t last = 200000;
  std::atomic<std::int64_t> reader_seen{0};
  std::thread writer([&] {
    for (std::int64_t i = 1; i <= last; ++i) {
      buffer.back().entries.fill(i);
      buffer.publish();
      // Every 1000 values, wait until the reader has seen this one, so the two really
      // interleave and the reader is guaranteed at least last / 1000 updates.
      while (i % 1000 == 0 && reader_seen.load() < i) std::this_thread::yield();
    }
  });
  std::int64_t seen = 0, updates = 0;
  while (seen < last) {
    if (!buffer.update()) continue;
    ++updates;
    const Stamp& s = buffer.front();
    ASSERT_TRUE(s.consistent()) << "torn value at " << s.entries[0];
    ASSERT_GT(s.entries[0], seen) << "a value older than one already seen";
    seen = s.entries[0];
    reader_seen.store(seen);
  }
  writer.join();
  EXPECT_EQ(seen, last);
  EXPECT_GE(updates, last / 1000);
  EXPECT_FALSE(buffer.update());  // nothing newer
}

TEST(CommandQueue, KeepsOrderRefusesWhenFullAndWorksAcrossThreads) {
  CommandQueue<int, 4> queue;
  for (int i = 0; i < 4; ++i) EXPECT_TRUE(queue.push(i));
  EXPECT_FALSE(queue.push(99));
  int value = -1;
  for (int i = 0; i < 4; ++i) {
    ASSERT_TRUE(queue.pop(value));
    EXPECT_EQ(value, i);
  }
  EXPECT_FALSE(queue.pop(value));

  CommandQueue<std::int64_t, 64> shared;
  constexpr std::int64_t count = 100000;
  std::thread producer([&] {
    for (std::int64_t i = 0; i < count;) {
      if (shared.push(i)) ++i;
    }
  });
  std::int64_t expected = 0, item = 0;
  while (expected < count) {
    if (shared.pop(item)) {
      ASSERT_EQ(item, expected);
      ++expected;
    }
  }
  producer.join();
}

TEST(LoopTiming, PercentilesToTheMicrosecond) {
  LoopTiming timing(1000);
  std::vector<double> work;
  for (int i = 0; i < 1000; ++i) work.push_back(0.37 * i + 0.2);  // 0.2 … 369.8 µs
  for (std::size_t i = 0; i < work.size(); ++i) timing.record(work[i], 2.0, i % 100 == 0, 1);
  timing.record(5000.0, 3.0, true, 4);  // beyond the histogram
  work.push_back(5000.0);
  const LoopStatistics s = timing.summary();
  std::sort(work.begin(), work.end());
  EXPECT_EQ(s.cycles, 1001);
  EXPECT_EQ(s.deadline_misses, 11);
  EXPECT_EQ(s.skipped_cycles, 1004);
  EXPECT_DOUBLE_EQ(s.max_work, 5000.0);
  EXPECT_DOUBLE_EQ(s.max_start_lateness, 3.0);
  double sum = 0.0;
  for (const double w : work) sum += w;
  EXPECT_NEAR(s.mean_work, sum / 1001.0, 1e-9);
  // Reported as the upper edge of the quantile's 1 µs bin.
  const double p50 = work[500], p99 = work[990];
  EXPECT_GE(s.p50_work, p50);
  EXPECT_LE(s.p50_work, p50 + 1.0);
  EXPECT_GE(s.p99_work, p99);
  EXPECT_LE(s.p99_work, p99 + 1.0);
  timing.clear();
  EXPECT_EQ(timing.summary().cycles, 0);
}

TEST(HapticLoop, RunsAtItsRateOnAbsoluteDeadlines) {
  LoopOptions options;
  options.rate_hz = 1000.0;
  HapticLoop loop(options);
  std::atomic<std::int64_t> cycles{0};
  std::atomic<bool> numbered{true};
  const auto before_start = std::chrono::steady_clock::now();
  loop.start([&](const CycleClock& clock) {
    if (clock.cycle != cycles.load()) numbered = false;
    if (std::abs(clock.period - 1e-3) > 1e-15) numbered = false;
    ++cycles;
  });
  const auto after_start = std::chrono::steady_clock::now();
  EXPECT_TRUE(loop.running());
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  const LoopStatistics running = loop.statistics();
  const auto before_stop = std::chrono::steady_clock::now();
  loop.stop();
  const auto after_stop = std::chrono::steady_clock::now();
  EXPECT_FALSE(loop.running());
  const LoopStatistics s = loop.statistics();
  EXPECT_TRUE(numbered);
  EXPECT_EQ(s.cycles, cycles.load());
  // Every period between start() and stop() was either run or counted as skipped (a loaded
  // machine skips periods rather than running cycles back to back); the first cycle starts one
  // period after start(), and stop() lets the current one finish. The bounds use the instants
  // around start() and stop(), so a test thread descheduled on a busy machine cannot break them.
  const auto ms = [](auto duration) {
    return std::chrono::duration<double, std::milli>(duration).count();
  };
  const double periods = static_cast<double>(s.cycles + s.skipped_cycles);
  EXPECT_GE(periods, ms(before_stop - after_start) - 2.0);
  EXPECT_LE(periods, ms(after_stop - before_start) + 1.0);
  EXPECT_GT(s.cycles, 100);
  EXPECT_LE(running.cycles, s.cycles);
  EXPECT_EQ(running.cycles % options.statistics_every, 0);
  EXPECT_LT(s.mean_work, 100.0);  // a counter increment
  loop.stop();                    // idempotent
}

TEST(HapticLoop, CountsMissedDeadlinesAndSkipsInsteadOfCatchingUp) {
  HapticLoop loop;
  std::atomic<std::int64_t> cycles{0};
  loop.start([&](const CycleClock& clock) {
    if (clock.cycle == 5) std::this_thread::sleep_for(std::chrono::microseconds(3500));
    ++cycles;
  });
  while (cycles.load() < 20) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  loop.stop();
  const LoopStatistics s = loop.statistics();
  EXPECT_GE(s.deadline_misses, 1);
  EXPECT_GE(s.skipped_cycles, 3);  // 3.5 ms of work: periods 6–8 are past when it ends
  EXPECT_GE(s.max_work, 3500.0);
}

TEST(HapticLoop, AThrowingCycleStopsTheLoopWithItsMessage) {
  HapticLoop loop;
  loop.start([](const CycleClock& clock) {
    if (clock.cycle == 3) throw std::runtime_error("device lost");
  });
  for (int i = 0; i < 1000 && loop.running(); ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  EXPECT_FALSE(loop.running());
  loop.stop();
  EXPECT_EQ(loop.error(), "device lost");
  EXPECT_EQ(loop.statistics().cycles, 3);
}

TEST(HapticLoop, RealTimePriorityAndPinningFallBackWithWarnings) {
  LoopOptions options;
  options.realtime_priority = true;
  options.cpu = 0;
  HapticLoop loop(options);
  loop.start([](const CycleClock&) {});
  // Granted (root, CAP_SYS_NICE) or refused with a warning that says what to grant.
  for (const std::string& warning : loop.warnings()) {
    EXPECT_TRUE(warning.find("SCHED_FIFO") != std::string::npos ||
                warning.find("CPU 0") != std::string::npos)
        << warning;
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(20));
  loop.stop();
  EXPECT_GT(loop.statistics().cycles, 5);
  EXPECT_THROW(HapticLoop(LoopOptions{.rate_hz = 0.0}), Error);
  EXPECT_THROW(loop.start(nullptr), Error);
}

/// The CPUs thread `thread` (0: the caller) may run on.
cpu_set_t affinity(pid_t thread = 0) {
  cpu_set_t set;
  CPU_ZERO(&set);
  EXPECT_EQ(sched_getaffinity(thread, sizeof(set), &set), 0);
  return set;
}

// While a pinned loop runs, no other thread of the process may use its CPU: the threads that
// existed (the test's, OpenMP's and OpenBLAS's pools) and the threads they start meanwhile, so
// precomputations run on the other cores and worker_threads() counts only those. Afterwards
// they have it back; a thread that was started during the loop too.
TEST(HapticLoop, APinnedLoopKeepsEveryOtherThreadOffItsCpu) {
  const cpu_set_t all = affinity();
  if (CPU_COUNT(&all) < 2) GTEST_SKIP() << "one CPU: the loop has to share it";
  int cpu = CPU_SETSIZE - 1;
  while (!CPU_ISSET(cpu, &all)) --cpu;
  reduced::set_worker_threads(0);
  // Pools of worker threads exist before the loop starts.
  EXPECT_GT(reduced::worker_threads(), 1);
  HapticLoop loop(LoopOptions{.cpu = cpu});
  std::atomic<pid_t> loop_thread{0};
  loop.start([&](const CycleClock&) { loop_thread = gettid(); });
  ASSERT_TRUE(loop.warnings().empty()) << loop.warnings().front();
  while (loop_thread.load() == 0) std::this_thread::yield();

  std::atomic<bool> release{false};
  std::atomic<pid_t> started_during{0};
  std::thread worker([&] {
    started_during = gettid();
    while (!release.load()) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  });
  while (started_during.load() == 0) std::this_thread::yield();
  int others = 0;
  for (const pid_t thread : test::process_threads()) {
    const cpu_set_t mask = affinity(thread);
    if (thread == loop_thread.load()) {
      EXPECT_EQ(CPU_COUNT(&mask), 1);
      EXPECT_TRUE(CPU_ISSET(cpu, &mask));
      continue;
    }
    ++others;
    EXPECT_FALSE(CPU_ISSET(cpu, &mask)) << "thread " << thread << " may run on CPU " << cpu;
  }
  EXPECT_GE(others, 2);  // the test's thread and the one it started, at least
  EXPECT_EQ(reduced::worker_threads(), CPU_COUNT(&all) - 1);
  loop.stop();

  const cpu_set_t after = affinity();
  EXPECT_TRUE(CPU_EQUAL(&after, &all));
  const cpu_set_t started = affinity(started_during.load());
  EXPECT_TRUE(CPU_EQUAL(&started, &all));
  EXPECT_EQ(reduced::worker_threads(), CPU_COUNT(&all));
  release = true;
  worker.join();
}

}  // namespace
}  // namespace khz::haptic
