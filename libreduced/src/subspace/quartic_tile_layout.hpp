#pragma once
// The order in which PolynomialForces stores and streams the energy polynomial's coefficients.

#include "simd_lanes.hpp"

#include <khz/reduced/subspace/energy_polynomial.hpp>

#include <Eigen/Core>

namespace khz::reduced::detail {

/// Coefficients of an EnergyPolynomial in r coordinates, homogenized and tiled for evaluation.
///
/// Homogenized: with q̂ = (q, 1) ∈ Rⁿ, n = r + 1, the whole energy is one quartic form
/// Ê(q̂) = Σ_{a≤b≤c≤d<n} T̂_abcd q̂_a q̂_b q̂_c q̂_d (thesis §2.6.4: "augmenting q to (q, 1)"):
/// T̂ holds T where d < r, C_abc where d = r > c, the quadratic part where c = d = r, and zeros
/// where b = r. So one kernel handles all degrees, and Euler's identity holds for Ê.
///
/// Tiled: the monomials are grouped into blocks by their two largest indices c ≤ d, stored one
/// after the other, c-major then d. Block (c, d) holds the symmetric (c+1)×(c+1) matrix X̃_cd
/// whose quadratic form is q̂'ᵀ X̃_cd q̂' = Σ_{a≤b≤c} T̂_abcd q̂_a q̂_b (q̂' = q̂[0..c]):
/// X̃[a][a] = T̂_aacd, X̃[a][b] = X̃[b][a] = ½ T̂_abcd. Its rows and columns are cut into groups
/// of kLanes = 8, and the block is stored column by column, column b of group g = b / 8 keeping
/// rows 0 to the end of its group: the strictly-upper off-diagonal 8×8 tiles once (each entry
/// standing for itself and its mirror), the diagonal tiles in full. Every stored column is then a
/// few 8-lane vectors, the last one partial only in the block's last group, and a block product
/// X̃ q̂' needs row-weighted sums of every column (vector FMAs) plus column-weighted sums of the
/// off-diagonal tiles only (one transposed horizontal sum per group of eight columns). Blocks are
/// zero-padded to whole tiles, so that every block starts on a 64-byte boundary.
class QuarticTileLayout {
 public:
  /// The layout for an r-coordinate polynomial (r ≥ 0).
  explicit QuarticTileLayout(Eigen::Index r);

  /// n = r + 1, the homogenized dimension.
  int coordinates() const noexcept { return m_coordinates; }
  /// Doubles in the whole layout (blocks of all c ≤ d).
  Eigen::Index size() const noexcept { return m_size; }

  /// Doubles in one block with second-largest index c: its columns, then zeros to a whole tile.
  static Eigen::Index block_size(int c) noexcept {
    const Eigen::Index groups = c / kLanes + 1;
    const Eigen::Index last_width = c + 1 - kLanes * (groups - 1);
    const Eigen::Index columns = kLanes * kLanes * groups * (groups - 1) / 2 + last_width * (c + 1);
    return (columns + kLanes - 1) / kLanes * kLanes;
  }

  /// Writes the coefficients of `polynomial` (dimension r, validated by the caller) to
  /// coefficients[0..size()) in layout order. Allocates nothing.
  void fill(const EnergyPolynomial& polynomial, double* coefficients) const noexcept;

  /// Weights w[0..block_size(c)) in block order with Σ w·X = q̂'ᵀ X̃ q̂' for any block X of
  /// index c: q̂_a q̂_b on diagonal tiles, 2 q̂_a q̂_b on the once-stored off-diagonal tiles, zero
  /// on the padding. q has whole tiles (zero-padded) up to the end of c's group.
  static void pair_weights(int c, const double* q, double* weights) noexcept;

  /// Calls visit(b, tile_row, rows) for each column b = 0..c of a block of index c, in storage
  /// order: the column holds rows [0, rows), of which [0, tile_row) are off-diagonal tiles and
  /// [tile_row, rows) the diagonal tile.
  template <typename Visit>
  static void for_each_column(int c, Visit&& visit) {
    for (int b = 0; b <= c; ++b) {
      const int tile_row = b - b % kLanes;
      const int rows = tile_row + kLanes <= c + 1 ? tile_row + kLanes : c + 1;
      visit(b, tile_row, rows);
    }
  }

 private:
  int m_coordinates;
  Eigen::Index m_size;
};

}  // namespace khz::reduced::detail
