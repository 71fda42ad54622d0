#pragma once
// a·b + c with the rounding fixed by the source, not by the compiler.

#include <cmath>

namespace khz::contact::detail {

/// a·b + c as one fused operation (one rounding) where the target has FMA instructions, and as a
/// product then a sum (two roundings) where it has none, in which case no compiler can fuse it
/// either. Inline code written with it rounds the same in every function it is inlined into,
/// whatever contraction (-ffp-contract) and tuning the caller is compiled with: what lets two
/// entry points promise the same value bit for bit on any CPU.
inline double multiply_add(double a, double b, double c) noexcept {
#if defined(__FMA__) || defined(__FP_FAST_FMA)
  return std::fma(a, b, c);
#else
  return a * b + c;
#endif
}

}  // namespace khz::contact::detail
