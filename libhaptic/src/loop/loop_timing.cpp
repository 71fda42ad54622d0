#include <khz/haptic/loop/loop_statistics.hpp>

#include <algorithm>
#include <cmath>

namespace khz::haptic {

LoopTiming::LoopTiming(int histogram_microseconds)
    : m_histogram(static_cast<std::size_t>(std::max(histogram_microseconds, 1)) + 1, 0) {}

void LoopTiming::record(double work_microseconds, double start_lateness_microseconds, bool missed,
                        std::int64_t skipped) noexcept {
  const double work = std::max(work_microseconds, 0.0);
  const auto last = static_cast<double>(m_histogram.size() - 1);
  m_histogram[static_cast<std::size_t>(std::min(std::floor(work), last))] += 1;
  ++m_totals.cycles;
  m_totals.deadline_misses += missed ? 1 : 0;
  m_totals.skipped_cycles += skipped;
  m_totals.mean_work += work;  // the sum until summary()
  m_totals.max_work = std::max(m_totals.max_work, work);
  m_totals.max_start_lateness = std::max(m_totals.max_start_lateness, start_lateness_microseconds);
}

LoopStatistics LoopTiming::summary() const noexcept {
  LoopStatistics s = m_totals;
  if (s.cycles == 0) return s;
  s.mean_work = m_totals.mean_work / static_cast<double>(s.cycles);
  // The upper edge of the bin holding the quantile (the longest time for the last bin).
  const auto quantile = [&](double fraction) {
    const auto rank =
        static_cast<std::int64_t>(std::ceil(fraction * static_cast<double>(s.cycles)));
    std::int64_t seen = 0;
    for (std::size_t bin = 0; bin < m_histogram.size(); ++bin) {
      seen += m_histogram[bin];
      if (seen >= std::max<std::int64_t>(rank, 1)) {
        return bin + 1 == m_histogram.size() ? s.max_work
                                             : std::min(static_cast<double>(bin + 1), s.max_work);
      }
    }
    return s.max_work;
  };
  s.p50_work = quantile(0.5);
  s.p99_work = quantile(0.99);
  return s;
}

void LoopTiming::clear() noexcept {
  std::fill(m_histogram.begin(), m_histogram.end(), 0);
  m_totals = LoopStatistics{};
}

}  // namespace khz::haptic
