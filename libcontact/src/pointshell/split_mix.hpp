#pragma once
// Reproducible random numbers for pointshell generation: SplitMix64 (Steele, Lea & Flood 2014)
// is fixed by its definition, unlike <random>'s implementation-defined distributions, and as a
// counter-based generator (draw i of a stream is split_mix(key + i)) lets every sample be drawn
// on its own, on any thread.

#include <cstdint>

namespace khz::contact::detail {

/// The SplitMix64 output for state x.
constexpr std::uint64_t split_mix(std::uint64_t x) noexcept {
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

/// A uniform double in [0, 1) from the top 53 bits.
constexpr double unit_interval(std::uint64_t bits) noexcept {
  return static_cast<double>(bits >> 11) * 0x1.0p-53;
}

}  // namespace khz::contact::detail
