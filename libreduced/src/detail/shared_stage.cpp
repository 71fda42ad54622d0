#include "detail/shared_stage.hpp"

#include <khz/reduced/errors.hpp>

#include <algorithm>
#include <utility>
#include <vector>

namespace khz::reduced {

WorkGroup::~WorkGroup() = default;

namespace detail {

namespace {

std::string what_of(const std::exception_ptr& failure) {
  try {
    std::rethrow_exception(failure);
  } catch (const std::exception& e) {
    return e.what();
  } catch (...) {
    return "an exception that is not a std::exception";
  }
}

}  // namespace

SharedStage::SharedStage(WorkGroup* group, const ProgressCallback& callback, std::string_view name,
                         std::int64_t total)
    : m_group(group),
      m_callback(callback),
      m_name(name),
      m_total(std::max<std::int64_t>(total, 1)) {
  report();
}

void SharedStage::finish() {
  if (m_done != m_total) {
    m_done = m_total;
    report();
  }
  check_in(0);
}

void SharedStage::fail(std::exception_ptr failure) {
  if (m_mine.state == GroupStatus::State::failed) return;  // the first failure tells
  m_mine.state = GroupStatus::State::failed;
  m_mine.message = what_of(failure);
  m_own_failure = std::move(failure);
}

std::int64_t SharedStage::most_rounds(std::int64_t rounds) {
  if (!shared()) return rounds;
  // Each process's count in its own slot, summed: every process sees all of them.
  std::vector<double> counts(static_cast<std::size_t>(m_group->size()), 0.0);
  counts[static_cast<std::size_t>(m_group->rank())] = static_cast<double>(rounds);
  m_group->sum(counts);
  return static_cast<std::int64_t>(*std::max_element(counts.begin(), counts.end()));
}

void SharedStage::check_in(std::int64_t done) {
  m_mine.done = done;
  GroupStatus group = m_mine;
  int rank = 0;
  if (m_group) {
    group = m_group->checkpoint(m_mine);
    rank = m_group->rank();
  } else {
    group.rank = 0;  // this process alone
  }
  switch (group.state) {
    case GroupStatus::State::running:
      break;
    case GroupStatus::State::failed:
      if (group.rank == rank && m_own_failure) std::rethrow_exception(m_own_failure);
      throw Error(m_name + " failed on rank " + std::to_string(group.rank) + " of " +
                  std::to_string(m_group->size()) + ": " + group.message);
    case GroupStatus::State::cancelled:
      if (group.rank == rank) throw Cancelled(group.message);
      throw Cancelled(m_name + " cancelled on rank " + std::to_string(group.rank) + " of " +
                      std::to_string(m_group->size()));
  }
  if (done == 0 && group.done == 0) return;
  m_done = std::min(m_total, m_done + group.done);
  report();
}

void SharedStage::report() {
  if (!m_callback || m_mine.state != GroupStatus::State::running) return;
  bool go_on = true;
  try {
    go_on = m_callback(Progress{m_name, m_done, m_total});
  } catch (...) {
    if (!m_group) throw;
    fail(std::current_exception());
    return;
  }
  if (go_on) return;
  if (!m_group) throw Cancelled("cancelled during " + m_name);
  m_mine.state = GroupStatus::State::cancelled;
  m_mine.message = "cancelled during " + m_name;
}

bool same_on_every_process(WorkGroup* group, std::span<const double> values) {
  if (!group || group->size() == 1) return true;
  // The mean over the processes, then the spread about it: zero iff every value equals the mean
  // (exact while the sums of the values are).
  std::vector<double> mean(values.begin(), values.end());
  group->sum(mean);
  std::vector<double> spread(values.size());
  for (std::size_t i = 0; i < values.size(); ++i) {
    mean[i] /= group->size();
    spread[i] = (values[i] - mean[i]) * (values[i] - mean[i]);
  }
  group->sum(spread);
  return std::all_of(spread.begin(), spread.end(), [](double s) { return s == 0.0; });
}

}  // namespace detail
}  // namespace khz::reduced
