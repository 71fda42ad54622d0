#include "detail/shared_stage.hpp"

#include <khz/reduced/errors.hpp>

#include <algorithm>
#include <utility>
#include <vector>

namespace khz::reduced {

namespace detail {

namespace {

/// Collective: every process's `values`, process after process (size × values.size() entries):
/// each process fills its own slot of zeros and the slots are summed, which adds nothing but
/// zeros to any value, so every process receives them exactly.
std::vector<double> from_every_process(WorkGroup& group, std::span<const double> values) {
  std::vector<double> all(static_cast<std::size_t>(group.size()) * values.size(), 0.0);
  std::copy(values.begin(), values.end(),
            all.begin() + static_cast<std::ptrdiff_t>(static_cast<std::size_t>(group.rank()) *
                                                      values.size()));
  group.sum(all);
  return all;
}

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
  return static_cast<std::int64_t>(largest_on_every_process(*m_group, static_cast<double>(rounds)));
}

double largest_on_every_process(WorkGroup& group, double value) {
  const std::vector<double> all = from_every_process(group, {&value, 1});
  return *std::max_element(all.begin(), all.end());
}

void SharedStage::check_in(std::int64_t done) {
  m_mine.done = done;
  GroupStatus group = m_mine;
  if (m_group) {
    group = m_group->checkpoint(m_mine);
    stop_unless_running(group, m_group->rank(), m_group->size(), m_name, m_own_failure);
  } else {
    group.rank = 0;  // this process alone
    stop_unless_running(group, 0, 1, m_name, m_own_failure);
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
  const std::vector<double> all = from_every_process(*group, values);
  for (std::size_t at = 0; at < all.size(); at += values.size()) {
    if (!std::equal(values.begin(), values.end(), all.begin() + static_cast<std::ptrdiff_t>(at))) {
      return false;
    }
  }
  return true;
}

}  // namespace detail
}  // namespace khz::reduced
