#pragma once
// Evaluation of a homogenized quartic energy stored in QuarticTileLayout order: its Hessian, its
// gradient and its value, each in one pass over the coefficients.

#include "quartic_tile_layout.hpp"
#include "simd_lanes.hpp"

#include <Eigen/Core>

#include <vector>

namespace khz::reduced::detail {

/// Working memory of the kernels for one layout, allocated once. Not shared between threads.
struct QuarticScratch {
  explicit QuarticScratch(const QuarticTileLayout& layout);

  Eigen::VectorXd weights;         ///< QuarticTileLayout::pair_weights of one c.
  std::vector<Lanes> pair_sums;    ///< Unreduced q̂'ᵀ X̃_cd q̂' (or sums of them), one per d.
  std::vector<Lanes> q_tiles;      ///< q̂ in lanes, when a block has more than 8 groups.
  std::vector<Lanes> product;      ///< A block product, when a block has more than 8 groups,
                                   ///< and Ĥ q̂ in symmetrize_halves.
  std::vector<Lanes> product_sum;  ///< A sum of block products, likewise.
};

/// Lanes-padded length of a homogenized vector: the kernels read and write q̂, gradients and
/// matrix columns in whole 8-lane tiles, so buffers have padded_length(n) entries.
inline Eigen::Index padded_length(int n) noexcept { return (n + kLanes - 1) / kLanes * kLanes; }

/// Writes M with Ĥ(q̂) = M + Mᵀ (the Hessian of the homogenized energy Ê): n columns of
/// padded_length(n) rows each, column-major. `q` is q̂ padded with zeros, `coefficients` in
/// layout order.
void hessian_halves(const QuarticTileLayout& layout, const double* coefficients, const double* q,
                    double* halves, QuarticScratch& scratch) noexcept;

/// From the halves M of hessian_halves: K̃ = (M + Mᵀ)[0..r)² (r = n − 1) into `stiffness`
/// (column-major, columns `stiffness_stride` doubles apart) and R̃ = ⅓ ((M + Mᵀ) q̂)[0..r) into
/// `forces` (Euler's identity for the homogeneous Ê), a pair of 8×8 tiles at a time.
void symmetrize_halves(const QuarticTileLayout& layout, const double* halves, const double* q,
                       double* stiffness, Eigen::Index stiffness_stride, double* forces,
                       QuarticScratch& scratch) noexcept;

/// Writes ∇Ê(q̂) to gradient[0..n) (and zeros to the padding up to padded_length(n)).
void homogenized_gradient(const QuarticTileLayout& layout, const double* coefficients,
                          const double* q, double* gradient, QuarticScratch& scratch) noexcept;

/// Ê(q̂).
double homogenized_energy(const QuarticTileLayout& layout, const double* coefficients,
                          const double* q, QuarticScratch& scratch) noexcept;

}  // namespace khz::reduced::detail
