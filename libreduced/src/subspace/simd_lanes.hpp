#pragma once
// Eight double lanes: the vector type the polynomial force kernels are written in. AVX-512 when
// the compiler targets it (Release builds use -march=native), otherwise plain arrays that the
// compiler may vectorize with whatever it has. The two agree up to rounding (fused or separate
// multiply-adds, the order of the additions in the horizontal sums).

#if defined(__AVX512F__)
#include <immintrin.h>
#endif

namespace khz::reduced::detail {

/// Number of lanes: the tile edge of the coefficient layout (QuarticTileLayout).
inline constexpr int kLanes = 8;

#if defined(__AVX512F__)

struct Lanes {
  __m512d v;
};

inline __mmask8 first_lanes_mask(int count) noexcept {
  return static_cast<__mmask8>((1u << count) - 1u);
}

inline Lanes zero_lanes() noexcept { return {_mm512_setzero_pd()}; }
/// Lane 0.
inline double first_lane(Lanes x) noexcept { return _mm512_cvtsd_f64(x.v); }
/// x with lane i (0 ≤ i < 8) replaced by value.
inline Lanes with_lane(Lanes x, int i, double value) noexcept {
  return {_mm512_mask_broadcastsd_pd(x.v, static_cast<__mmask8>(1u << i), _mm_set_sd(value))};
}
inline Lanes broadcast(double value) noexcept { return {_mm512_set1_pd(value)}; }
/// Lanes p[0..8), any alignment.
inline Lanes load(const double* p) noexcept { return {_mm512_loadu_pd(p)}; }
/// Lanes p[0..count), the others zero; reads nothing beyond p + count (0 < count ≤ 8).
inline Lanes load_first(const double* p, int count) noexcept {
  return {_mm512_maskz_loadu_pd(first_lanes_mask(count), p)};
}
inline void store(double* p, Lanes x) noexcept { _mm512_storeu_pd(p, x.v); }
/// Writes lanes [0, count) to p[0..count) and nothing else (0 < count ≤ 8).
inline void store_first(double* p, Lanes x, int count) noexcept {
  _mm512_mask_storeu_pd(p, first_lanes_mask(count), x.v);
}
/// a·b + c lane by lane.
inline Lanes fma(Lanes a, Lanes b, Lanes c) noexcept { return {_mm512_fmadd_pd(a.v, b.v, c.v)}; }
inline Lanes operator+(Lanes a, Lanes b) noexcept { return {_mm512_add_pd(a.v, b.v)}; }
inline Lanes operator*(Lanes a, Lanes b) noexcept { return {_mm512_mul_pd(a.v, b.v)}; }
// Shuffles are spelled with __builtin_shufflevector: GCC 12's shuffle intrinsics pass an
// undefined vector that -Wuninitialized reports (GCC bug 105593).

/// The sum of the lanes.
inline double sum(Lanes x) noexcept {
  using Half = double __attribute__((vector_size(32)));
  using Quarter = double __attribute__((vector_size(16)));
  const Half half =
      __builtin_shufflevector(x.v, x.v, 0, 1, 2, 3) + __builtin_shufflevector(x.v, x.v, 4, 5, 6, 7);
  const Quarter quarter =
      __builtin_shufflevector(half, half, 0, 1) + __builtin_shufflevector(half, half, 2, 3);
  return quarter[0] + quarter[1];
}
/// Lane i of the result is sum(x[i]): eight horizontal sums for the price of about two, by
/// transposing while adding (pairs of vectors, then 128-bit lanes, then 256-bit halves).
inline Lanes transpose_sum(const Lanes (&x)[kLanes]) noexcept {
  const auto pair = [](__m512d a, __m512d b) -> __m512d {
    return __builtin_shufflevector(a, b, 0, 8, 2, 10, 4, 12, 6, 14) +
           __builtin_shufflevector(a, b, 1, 9, 3, 11, 5, 13, 7, 15);
  };
  const auto quad = [](__m512d a, __m512d b) -> __m512d {
    return __builtin_shufflevector(a, b, 0, 1, 4, 5, 8, 9, 12, 13) +
           __builtin_shufflevector(a, b, 2, 3, 6, 7, 10, 11, 14, 15);
  };
  const __m512d low = quad(pair(x[0].v, x[1].v), pair(x[2].v, x[3].v));
  const __m512d high = quad(pair(x[4].v, x[5].v), pair(x[6].v, x[7].v));
  return {quad(low, high)};
}
/// Transposes the 8×8 matrix whose columns are x[0..8), in place (24 shuffles).
inline void transpose(Lanes (&x)[kLanes]) noexcept {
  __m512d t[kLanes], u[kLanes];
  for (int k = 0; k < kLanes; k += 2) {
    t[k] = __builtin_shufflevector(x[k].v, x[k + 1].v, 0, 8, 2, 10, 4, 12, 6, 14);
    t[k + 1] = __builtin_shufflevector(x[k].v, x[k + 1].v, 1, 9, 3, 11, 5, 13, 7, 15);
  }
  for (int k = 0; k < kLanes; k += 4) {
    for (int h = 0; h < 2; ++h) {
      u[k + h] = __builtin_shufflevector(t[k + h], t[k + h + 2], 0, 1, 8, 9, 4, 5, 12, 13);
      u[k + h + 2] = __builtin_shufflevector(t[k + h], t[k + h + 2], 2, 3, 10, 11, 6, 7, 14, 15);
    }
  }
  for (int k = 0; k < 4; ++k) {
    x[k].v = __builtin_shufflevector(u[k], u[k + 4], 0, 1, 2, 3, 8, 9, 10, 11);
    x[k + 4].v = __builtin_shufflevector(u[k], u[k + 4], 4, 5, 6, 7, 12, 13, 14, 15);
  }
}

#else

struct Lanes {
  double v[kLanes];
};

inline Lanes zero_lanes() noexcept { return {}; }
inline double first_lane(Lanes x) noexcept { return x.v[0]; }
inline Lanes with_lane(Lanes x, int i, double value) noexcept {
  x.v[i] = value;
  return x;
}
inline Lanes broadcast(double value) noexcept {
  Lanes x;
  for (double& lane : x.v) lane = value;
  return x;
}
inline Lanes load(const double* p) noexcept {
  Lanes x;
  for (int i = 0; i < kLanes; ++i) x.v[i] = p[i];
  return x;
}
inline Lanes load_first(const double* p, int count) noexcept {
  Lanes x{};
  for (int i = 0; i < count; ++i) x.v[i] = p[i];
  return x;
}
inline void store(double* p, Lanes x) noexcept {
  for (int i = 0; i < kLanes; ++i) p[i] = x.v[i];
}
inline void store_first(double* p, Lanes x, int count) noexcept {
  for (int i = 0; i < count; ++i) p[i] = x.v[i];
}
inline Lanes fma(Lanes a, Lanes b, Lanes c) noexcept {
  for (int i = 0; i < kLanes; ++i) c.v[i] += a.v[i] * b.v[i];
  return c;
}
inline Lanes operator+(Lanes a, Lanes b) noexcept {
  for (int i = 0; i < kLanes; ++i) a.v[i] += b.v[i];
  return a;
}
inline Lanes operator*(Lanes a, Lanes b) noexcept {
  for (int i = 0; i < kLanes; ++i) a.v[i] *= b.v[i];
  return a;
}
inline double sum(Lanes x) noexcept {
  double total = 0.0;
  for (double lane : x.v) total += lane;
  return total;
}
inline Lanes transpose_sum(const Lanes (&x)[kLanes]) noexcept {
  Lanes result;
  for (int i = 0; i < kLanes; ++i) result.v[i] = sum(x[i]);
  return result;
}
inline void transpose(Lanes (&x)[kLanes]) noexcept {
  for (int i = 0; i < kLanes; ++i) {
    for (int j = i + 1; j < kLanes; ++j) {
      const double swapped = x[i].v[j];
      x[i].v[j] = x[j].v[i];
      x[j].v[i] = swapped;
    }
  }
}

#endif

}  // namespace khz::reduced::detail
