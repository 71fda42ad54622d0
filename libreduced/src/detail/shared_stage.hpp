#pragma once
// One stage of a precomputation whose units are shared among the processes of a WorkGroup, or
// done by this process alone. The work runs in rounds; after each, every process reports the
// group's progress to its own callback and meets the others at a checkpoint, so that a failure
// or a cancel on any process stops every process at the same point, before the next collective.

#include <khz/reduced/progress.hpp>
#include <khz/reduced/work_group.hpp>

#include <algorithm>
#include <cstdint>
#include <exception>
#include <span>
#include <string>
#include <string_view>

namespace khz::reduced::detail {

class SharedStage {
 public:
  /// Reports 0 of `total` units of `name` to `callback`. `group` null: this process alone.
  /// @throws Cancelled if the callback says stop and there is no group (with a group, the
  ///         cancel reaches every process at the first checkpoint).
  SharedStage(WorkGroup* group, const ProgressCallback& callback, std::string_view name,
              std::int64_t total);

  /// Whether units are shared with other processes.
  bool shared() const noexcept { return m_group != nullptr && m_group->size() > 1; }

  /// Runs this process's share of `count` units (share_of()), `per_round` at a time (which may
  /// differ between processes): work(begin, end) on the calling thread for each round's range,
  /// then a checkpoint crediting end − begin units. Every process goes through the same number
  /// of rounds, the most any process needs (a collective when shared); those with nothing left
  /// check in with empty ranges and no call. An exception from `work` skips the process's
  /// remaining rounds and stops every process at the round's checkpoint.
  /// @throws what a process's work threw (the original exception on that process, Error naming
  ///         the rank on the others); Cancelled if any process's callback said stop.
  template <typename Work>
  void run(std::int64_t count, std::int64_t per_round, const Work& work) {
    const int rank = m_group ? m_group->rank() : 0;
    const int size = m_group ? m_group->size() : 1;
    const auto [begin, end] = share_of(count, rank, size);
    const std::int64_t largest = (count + size - 1) / size;
    // Processes with fewer threads may take smaller rounds, but all meet equally often.
    const std::int64_t rounds = most_rounds((largest + per_round - 1) / per_round);
    for (std::int64_t round = 0; round < rounds; ++round) {
      const std::int64_t first = std::min(end, begin + round * per_round);
      const std::int64_t last = std::min(end, first + per_round);
      if (first < last && m_mine.state == GroupStatus::State::running) {
        try {
          work(first, last);
        } catch (...) {
          fail(std::current_exception());
        }
      }
      check_in(last - first);
    }
  }

  /// Runs all `count` units on every process, `per_round` at a time (work the processes must do
  /// together, e.g. the solves of a factorization distributed over them), with a checkpoint
  /// after each round that credits the round's units once (the first process's count).
  /// @throws as run().
  template <typename Work>
  void run_on_every_process(std::int64_t count, std::int64_t per_round, const Work& work) {
    const bool counts = !m_group || m_group->rank() == 0;
    for (std::int64_t first = 0; first < count; first += per_round) {
      const std::int64_t last = std::min(count, first + per_round);
      if (m_mine.state == GroupStatus::State::running) {
        try {
          work(first, last);
        } catch (...) {
          fail(std::current_exception());
        }
      }
      check_in(counts ? last - first : 0);
    }
  }

  /// Runs `step` on this process (e.g. checking its inputs), then meets the others, so that
  /// a step that throws on one process stops them all before their next collective.
  /// @throws as run().
  template <typename Step>
  void agree(const Step& step) {
    if (m_mine.state == GroupStatus::State::running) {
      try {
        step();
      } catch (...) {
        fail(std::current_exception());
      }
    }
    check_in(0);
  }

  /// Reports the stage complete and meets the others a last time.
  /// @throws as run().
  void finish();

  /// Reports the progress so far again, within a long unit of work, so that a cancel is seen:
  /// without a group a stop throws Cancelled at once; with one it stops every process at the
  /// next checkpoint.
  void poll() { report(); }

 private:
  void fail(std::exception_ptr failure);
  /// The largest `rounds` over the group (this process's own without one).
  std::int64_t most_rounds(std::int64_t rounds);
  /// The checkpoint: throws what stopped any process, else credits the group's units and
  /// reports them.
  void check_in(std::int64_t done);
  /// Calls the callback; a stop or an exception is thrown at once without a group, kept for the
  /// next checkpoint with one.
  void report();

  WorkGroup* m_group;
  const ProgressCallback& m_callback;
  std::string m_name;
  std::int64_t m_total;
  std::int64_t m_done = 0;
  GroupStatus m_mine;                // what this process brings to the next checkpoint
  std::exception_ptr m_own_failure;  // rethrown here when the group stops for it
};

/// Collective: the largest `value` passed by the processes of `group`.
double largest_on_every_process(WorkGroup& group, double value);

/// Collective: whether every process of `group` passed the same `values` (e.g. sizes that must
/// agree before partial sums are added), compared exactly; true without a group.
bool same_on_every_process(WorkGroup* group, std::span<const double> values);

}  // namespace khz::reduced::detail
