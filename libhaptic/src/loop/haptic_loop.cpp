#include <khz/haptic/loop/haptic_loop.hpp>

#include "other_threads_off_cpu.hpp"

#include <pthread.h>
#include <sched.h>
#include <time.h>

#include <chrono>
#include <cmath>
#include <cstring>
#include <future>
#include <optional>
#include <string>

namespace khz::haptic {
namespace {

using Clock = std::chrono::steady_clock;  // CLOCK_MONOTONIC on Linux

/// Sleeps until `when` on CLOCK_MONOTONIC (absolute: a late wake-up does not shift later
/// deadlines).
void sleep_until(Clock::time_point when) noexcept {
  const auto since_epoch =
      std::chrono::duration_cast<std::chrono::nanoseconds>(when.time_since_epoch()).count();
  timespec deadline{};
  deadline.tv_sec = static_cast<time_t>(since_epoch / 1000000000);
  deadline.tv_nsec = static_cast<long>(since_epoch % 1000000000);
  while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &deadline, nullptr) == EINTR) {
  }
}

double microseconds(Clock::duration d) noexcept {
  return std::chrono::duration<double, std::micro>(d).count();
}

}  // namespace

void LoopOptions::validate() const {
  if (!(rate_hz > 0.0 && rate_hz <= 100000.0)) {
    throw Error("LoopOptions: rate_hz must be in (0, 100000], got " + std::to_string(rate_hz));
  }
  if (priority < 1 || priority > 99) {
    throw Error("LoopOptions: priority must be in [1, 99], got " + std::to_string(priority));
  }
  if (cpu < -1)
    throw Error("LoopOptions: cpu must be ≥ 0, or −1 for none, got " + std::to_string(cpu));
  if (statistics_every < 1) {
    throw Error("LoopOptions: statistics_every must be ≥ 1, got " +
                std::to_string(statistics_every));
  }
}

HapticLoop::HapticLoop(const LoopOptions& options) : m_options(options) { options.validate(); }

HapticLoop::~HapticLoop() { stop(); }

void HapticLoop::start(Cycle cycle) {
  if (m_thread.joinable()) throw Error("HapticLoop::start: the loop is already running");
  if (!cycle) throw Error("HapticLoop::start: no cycle to run");
  m_cycle = std::move(cycle);
  m_stop.store(false);
  m_warnings.clear();
  m_error.clear();
  m_timing.clear();
  m_published.reset(LoopStatistics{});
  m_stopped_once = false;
  std::promise<void> ready;
  std::future<void> started = ready.get_future();
  m_running.store(true, std::memory_order_release);
  m_thread = std::thread([this, promise = std::move(ready)]() mutable { run(promise); });
  started.wait();
}

void HapticLoop::stop() noexcept {
  m_stop.store(true, std::memory_order_release);
  if (m_thread.joinable()) m_thread.join();
  if (!m_stopped_once) {
    m_final = m_timing.summary();
    m_stopped_once = true;
  }
}

LoopStatistics HapticLoop::statistics() noexcept {
  if (!m_thread.joinable() || m_stopped_once) return m_stopped_once ? m_final : LoopStatistics{};
  m_published.update();
  return m_published.front();
}

void HapticLoop::run(std::promise<void>& ready) noexcept {
  // Set-up: CPU pin and priority, each a warning when refused. A pinned loop has its CPU to
  // itself: the process's other threads, and the worker threads they start, run elsewhere.
  std::optional<detail::OtherThreadsOffCpu> others_off;
  if (m_options.cpu >= 0) {
    cpu_set_t set;
    CPU_ZERO(&set);
    CPU_SET(m_options.cpu, &set);
    const int code = pthread_setaffinity_np(pthread_self(), sizeof(set), &set);
    if (code != 0) {
      m_warnings.push_back("HapticLoop: could not pin the loop to CPU " +
                           std::to_string(m_options.cpu) + " (" + std::strerror(code) +
                           "); it runs on any CPU");
    } else {
      try {
        others_off.emplace(m_options.cpu);
        for (const std::string& failure : others_off->failures()) {
          m_warnings.push_back("HapticLoop: could not keep " + failure + " off CPU " +
                               std::to_string(m_options.cpu));
        }
      } catch (const std::exception& error) {
        m_warnings.push_back("HapticLoop: could not keep other threads off CPU " +
                             std::to_string(m_options.cpu) + " (" + error.what() + ")");
      }
    }
  }
  if (m_options.realtime_priority) {
    sched_param parameter{};
    parameter.sched_priority = m_options.priority;
    const int code = pthread_setschedparam(pthread_self(), SCHED_FIFO, &parameter);
    if (code != 0) {
      m_warnings.push_back("HapticLoop: real-time priority (SCHED_FIFO " +
                           std::to_string(m_options.priority) + ") refused (" +
                           std::strerror(code) +
                           "); the loop runs at normal priority (grant CAP_SYS_NICE or an rtprio "
                           "limit to allow it)");
    }
  }
  // t₀ is fixed before start() returns, so a caller's clock read after start() is never ahead
  // of the loop's.
  const auto period = std::chrono::duration_cast<Clock::duration>(
      std::chrono::duration<double>(1.0 / m_options.rate_hz));
  const Clock::time_point start = Clock::now() + period;
  ready.set_value();

  std::int64_t slot = 0;  // periods since start
  CycleClock clock;
  clock.period = 1.0 / m_options.rate_hz;
  try {
    while (!m_stop.load(std::memory_order_acquire)) {
      const Clock::time_point scheduled = start + slot * period;
      sleep_until(scheduled);
      const Clock::time_point woke = Clock::now();
      clock.time = static_cast<double>(slot) * clock.period;
      m_cycle(clock);
      const Clock::time_point end = Clock::now();
      // The next slot that has not begun yet: skipped periods are not run back to back.
      const std::int64_t next = (end - start) / period + 1;
      const std::int64_t skipped = std::max<std::int64_t>(next - slot - 1, 0);
      m_timing.record(microseconds(end - woke), microseconds(woke - scheduled),
                      end > scheduled + period, skipped);
      slot = std::max(next, slot + 1);
      ++clock.cycle;
      if (clock.cycle % m_options.statistics_every == 0) {
        m_published.back() = m_timing.summary();
        m_published.publish();
      }
    }
  } catch (const std::exception& error) {
    m_error = error.what();
  } catch (...) {
    m_error = "HapticLoop: the cycle threw a non-standard exception";
  }
  m_running.store(false, std::memory_order_release);
}

}  // namespace khz::haptic
