#pragma once
// Quantiles of a nonnegative quantity whose scale is not known in advance (forces in N, steps in
// m), accumulated without allocating: bins of equal ratio, so every quantile is known to the
// same relative resolution whatever the units.

#include <khz/haptic/world/cycle_metrics.hpp>

#include <cstdint>
#include <vector>

namespace khz::haptic::detail {

/// 64 bins per decade from 1e-12 to 1e6 (a bin's edges 3.7 % apart); values below the first bin
/// (zero included) are counted as zero, values above the last in the last bin. The maximum is
/// kept exactly.
class MagnitudeHistogram {
 public:
  MagnitudeHistogram();

  /// Counts one value (negative and NaN values count as zero). Allocation-free.
  void add(double value) noexcept;
  /// Nearest-rank p50 and p99, each the geometric centre of its bin (clamped to the maximum; 0
  /// for the bin of zeros), and the exact mean, maximum and count (negative and NaN values as
  /// zero). All zero before the first value.
  Quantiles quantiles() const noexcept;
  void clear() noexcept;

 private:
  double quantile(double fraction) const noexcept;

  std::vector<std::int64_t> m_bins;  // [0]: zeros and values below 1e-12
  std::int64_t m_count = 0;
  double m_sum = 0.0;
  double m_max = 0.0;
};

}  // namespace khz::haptic::detail
