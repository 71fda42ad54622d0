#pragma once
// Reports one stage of a long computation to a ProgressCallback and turns a cancel request
// into the Cancelled exception: what every Kilohertz precomputation uses, public so that the
// libraries built on libreduced (and users' own precomputations) keep the same contract.

#include <khz/reduced/errors.hpp>
#include <khz/reduced/progress.hpp>

#include <algorithm>
#include <cstdint>
#include <string>
#include <string_view>

namespace khz::reduced {

/// Counts the finished units of one stage; every report asks the callback whether to go on.
/// Call it from the thread that started the computation, outside OpenMP regions (an exception
/// must not leave one): parallel loops run in chunks with a report between chunks.
class StageProgress {
 public:
  /// Reports done = 0 of `total` (clamped to ≥ 1) units of `stage`.
  /// @throws Cancelled if the callback says stop.
  StageProgress(const ProgressCallback& callback, std::string_view stage, std::int64_t total)
      : m_callback(callback), m_stage(stage), m_total(std::max<std::int64_t>(total, 1)) {
    report();
  }

  /// Marks `units` more as finished (never past total) and reports.
  /// @throws Cancelled if the callback says stop.
  void advance(std::int64_t units = 1) {
    m_done = std::min(m_total, m_done + units);
    report();
  }

  /// Raises the total when the work turns out larger than estimated (never lowers it).
  void raise_total(std::int64_t total) noexcept { m_total = std::max(m_total, total); }
  std::int64_t done() const noexcept { return m_done; }
  std::int64_t total() const noexcept { return m_total; }

  /// Marks the stage complete (done = total) and reports, unless that was already reported.
  /// @throws Cancelled if the callback says stop.
  void finish() {
    if (m_done == m_total && m_reported_done == m_total) return;
    m_done = m_total;
    report();
  }

 private:
  void report() {
    m_reported_done = m_done;
    if (m_callback && !m_callback(Progress{m_stage, m_done, m_total})) {
      throw Cancelled("cancelled during " + std::string(m_stage));
    }
  }

  const ProgressCallback& m_callback;
  std::string_view m_stage;
  std::int64_t m_total;
  std::int64_t m_done = 0;
  std::int64_t m_reported_done = -1;
};

}  // namespace khz::reduced
