#include "magnitude_histogram.hpp"

#include <algorithm>
#include <cmath>

namespace khz::haptic::detail {

namespace {

constexpr double kSmallest = 1e-12;
constexpr int kBinsPerDecade = 64;
constexpr int kDecades = 18;  // 1e-12 … 1e6
constexpr int kBins = 1 + kBinsPerDecade * kDecades;

}  // namespace

MagnitudeHistogram::MagnitudeHistogram() : m_bins(kBins, 0) {}

void MagnitudeHistogram::add(double value) noexcept {
  ++m_count;
  if (!(value >= kSmallest)) {  // zero, negative or NaN
    ++m_bins[0];
    return;
  }
  m_sum += value;
  m_max = std::max(m_max, value);
  const double position = std::log10(value / kSmallest) * kBinsPerDecade;
  const int bin = 1 + std::min(static_cast<int>(position), kBins - 2);
  ++m_bins[static_cast<std::size_t>(bin)];
}

double MagnitudeHistogram::quantile(double fraction) const noexcept {
  // Nearest rank: the smallest value with at least ⌈fraction · count⌉ values at or below it.
  const auto rank = static_cast<std::int64_t>(std::ceil(fraction * static_cast<double>(m_count)));
  std::int64_t seen = 0;
  for (int bin = 0; bin < kBins; ++bin) {
    seen += m_bins[static_cast<std::size_t>(bin)];
    if (seen < std::max<std::int64_t>(rank, 1)) continue;
    if (bin == 0) return 0.0;
    const double centre = kSmallest * std::pow(10.0, (bin - 0.5) / kBinsPerDecade);
    return std::min(centre, m_max);
  }
  return m_max;
}

Quantiles MagnitudeHistogram::quantiles() const noexcept {
  if (m_count == 0) return {};
  return {m_sum / static_cast<double>(m_count), quantile(0.5), quantile(0.99), m_max, m_count};
}

void MagnitudeHistogram::clear() noexcept {
  std::fill(m_bins.begin(), m_bins.end(), 0);
  m_count = 0;
  m_sum = 0.0;
  m_max = 0.0;
}

}  // namespace khz::haptic::detail
