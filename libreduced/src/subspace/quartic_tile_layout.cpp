#include "quartic_tile_layout.hpp"

#include <algorithm>

namespace khz::reduced::detail {

namespace {

/// T̂_abcd of the homogenized polynomial for a ≤ b ≤ c ≤ d ≤ r (index r is the constant 1).
double homogenized_coefficient(const EnergyPolynomial& polynomial, int a, int b, int c,
                               int d) noexcept {
  const auto r = static_cast<int>(polynomial.dimension());
  if (d < r) return polynomial.quartic[EnergyPolynomial::quartic_index(a, b, c, d)];
  if (c < r) return polynomial.cubic[EnergyPolynomial::cubic_index(a, b, c)];
  if (b < r) {
    // ½ qᵀKq = Σ_a ½ K_aa q_a² + Σ_{a<b} K_ab q_a q_b, K symmetric to rounding.
    return a == b ? 0.5 * polynomial.quadratic(a, a)
                  : 0.5 * (polynomial.quadratic(a, b) + polynomial.quadratic(b, a));
  }
  return 0.0;  // Linear and constant terms: the energy has none.
}

}  // namespace

QuarticTileLayout::QuarticTileLayout(Eigen::Index r)
    : m_coordinates(static_cast<int>(r + 1)), m_size(0) {
  for (int c = 0; c < m_coordinates; ++c) m_size += (m_coordinates - c) * block_size(c);
}

void QuarticTileLayout::fill(const EnergyPolynomial& polynomial,
                             double* coefficients) const noexcept {
  for (int c = 0; c < m_coordinates; ++c) {
    for (int d = c; d < m_coordinates; ++d) {
      double* const end = coefficients + block_size(c);
      for_each_column(c, [&](int b, int /*tile_row*/, int rows) {
        for (int a = 0; a < rows; ++a) {
          const double t =
              homogenized_coefficient(polynomial, std::min(a, b), std::max(a, b), c, d);
          *coefficients++ = a == b ? t : 0.5 * t;
        }
      });
      std::fill(coefficients, end, 0.0);
      coefficients = end;
    }
  }
}

void QuarticTileLayout::pair_weights(int c, const double* q, double* weights) noexcept {
  double* const end = weights + block_size(c);
  for_each_column(c, [&](int b, int tile_row, int rows) {
    const Lanes qb = broadcast(q[b]);
    const Lanes two_qb = broadcast(2.0 * q[b]);
    for (int a = 0; a < tile_row; a += kLanes, weights += kLanes) {
      store(weights, two_qb * load(q + a));
    }
    store_first(weights, qb * load(q + tile_row), rows - tile_row);
    weights += rows - tile_row;
  });
  std::fill(weights, end, 0.0);
}

}  // namespace khz::reduced::detail
