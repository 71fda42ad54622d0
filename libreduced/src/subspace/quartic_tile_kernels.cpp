#include "quartic_tile_kernels.hpp"

#include <algorithm>
#include <type_traits>
#include <utility>

// Notation: n = r + 1 homogenized coordinates, q̂ ∈ Rⁿ, and per block (c ≤ d) the symmetric
// matrix X̃_cd of QuarticTileLayout, u_cd = X̃_cd q̂' and f_cd = q̂'ᵀ u_cd (q̂' = q̂[0..c]), so
// that Ê = Σ_{c≤d} q̂_c q̂_d f_cd. Differentiating each term g = m f with m = q̂_c q̂_d:
//   ∇g  = 2 m u + f ∇m,                                    ∇m = q̂_d e_c + q̂_c e_d,
//   ∇²g = 2 m X̃ + 2 (∇m uᵀ + u ∇mᵀ) + f (e_c e_dᵀ + e_d e_cᵀ).
// The Hessian kernel accumulates M with Ĥ = M + Mᵀ, so that each symmetric pair of terms is
// added once; the gradient kernel needs the block products u_cd and f_cd only.
//
// The tiles of a block product live in registers: every loop over tiles, groups and columns is
// unrolled at compile time (index sequences rather than loops, so that GCC's scalar replacement
// of the tile arrays sees constant indices) for blocks of up to kMaxRegisterGroups groups
// (r < 64). Larger blocks run the same code with the groups past the second in a run-time loop
// and their tiles in QuarticScratch.
//
// Each coefficient vector costs the Hessian three FMAs (row sums, column sums, the 2 q̂_c q̂_d X̃_cd
// term) where a gemv costs one, and the X̃ term is a load and a store of M besides. Blocks in
// registers are therefore taken two at a time (kBlocksTogether): both blocks' X̃ terms are added
// to a tile of M between one load and one store. Measured against one block at a time
// (bench_reduced_polynomials, evaluate): 9 % faster at r = 60, 6 % at r = 30.

namespace khz::reduced::detail {

QuarticScratch::QuarticScratch(const QuarticTileLayout& layout)
    : weights(QuarticTileLayout::block_size(layout.coordinates() - 1)),
      pair_sums(static_cast<std::size_t>(padded_length(layout.coordinates())), zero_lanes()),
      q_tiles(static_cast<std::size_t>(padded_length(layout.coordinates()) / kLanes)),
      product(q_tiles.size()),
      product_sum(q_tiles.size()) {}

namespace {

constexpr int kMaxRegisterGroups = 8;

/// What a block product does with the 2 q̂_c q̂_d X̃_cd term of the Hessian: nothing, add it to
/// the Hessian halves, or add it there except for the first group's eight columns (one tile
/// each), which are summed over d in registers (`first_group` of block_product).
enum class Sums { none, halves, halves_first_group_in_registers };

/// Where a block product adds its Hessian term: column b of the block to column b of M (stride
/// doubles apart) with weights 2 q̂_c q̂_d on the off-diagonal tiles (stored once, they stand for
/// both M and Mᵀ) and q̂_c q̂_d on the diagonal tiles (stored in full), one pair of weights for
/// each of the D blocks taken together.
template <int D>
struct SumTarget {
  double* halves;
  Eigen::Index stride;
  Lanes off_diagonal[D];
  Lanes diagonal[D];
};

template <int N>
using Index = std::integral_constant<int, N>;

template <typename F, int... I>
[[gnu::always_inline]] inline void unrolled(F&& f, std::integer_sequence<int, I...>) {
  (f(Index<I>{}), ...);
}

/// f(Index<0>{}), …, f(Index<N−1>{}): a loop unrolled by the compiler front end.
template <int N, typename F>
[[gnu::always_inline]] inline void unrolled(F&& f) {
  unrolled(f, std::make_integer_sequence<int, N>{});
}

/// f(i) for i in [0, count): unrolled if count is an Index, a run-time loop if it is an int.
template <typename Count, typename F>
[[gnu::always_inline]] inline void for_each_index(Count count, F&& f) {
  if constexpr (std::is_same_v<Count, int>) {
    for (int i = 0; i < count; ++i) f(i);
  } else {
    unrolled<Count::value>(f);
  }
}

/// Adds the `width` columns of group g of the D consecutive blocks at x (`block_size` doubles
/// apart) to their block products u + j·u_stride (see block_product), advancing x through the
/// first block. g is an Index (u in registers) or, past group 1 of a block of more than
/// kMaxRegisterGroups groups, an int (then D = 1).
template <int D, Sums kSums, typename Group>
[[gnu::always_inline]] inline void add_group(Group g, int width, const double*& x,
                                             Eigen::Index block_size, const double* q,
                                             const Lanes* q_tiles, Lanes* u, int u_stride,
                                             const SumTarget<D>& sums,
                                             Lanes* first_group) noexcept {
  // Column-weighted sums of the off-diagonal tiles above the diagonal tile, one per column.
  Lanes column_sums[D][kLanes];
  if (g > 0) {
    unrolled<D>(
        [&](auto j) { unrolled<kLanes>([&](auto i) { column_sums[j][i] = zero_lanes(); }); });
  }
  unrolled<kLanes>([&](auto i) {
    if (i >= width) return;
    const Lanes qb = broadcast(q[kLanes * g + i]);
    double* column = kSums == Sums::none ? nullptr : sums.halves + (kLanes * g + i) * sums.stride;
    for_each_index(g, [&](auto tile) {
      // The D blocks' Hessian terms are summed before M is stored: one load and store of M for
      // D coefficient vectors.
      Lanes halves_tile;
      if constexpr (kSums != Sums::none) halves_tile = load(column + kLanes * tile);
      unrolled<D>([&](auto j) {
        const Lanes xv = load(x + j * block_size);
        u[j * u_stride + tile] = fma(xv, qb, u[j * u_stride + tile]);
        column_sums[j][i] = fma(xv, q_tiles[tile], column_sums[j][i]);
        if constexpr (kSums != Sums::none) {
          halves_tile = fma(xv, sums.off_diagonal[j], halves_tile);
        }
      });
      if constexpr (kSums != Sums::none) store(column + kLanes * tile, halves_tile);
      x += kLanes;
    });
    // The diagonal tile, stored in full: row-weighted sums only.
    constexpr bool kInRegisters =
        kSums == Sums::halves_first_group_in_registers && std::is_same_v<Group, Index<0>>;
    Lanes halves_tile;
    if constexpr (kSums != Sums::none && !kInRegisters) halves_tile = load(column + kLanes * g);
    unrolled<D>([&](auto j) {
      const double* at = x + j * block_size;
      const Lanes xv = width == kLanes ? load(at) : load_first(at, width);
      u[j * u_stride + g] = fma(xv, qb, u[j * u_stride + g]);
      if constexpr (kInRegisters) {
        first_group[i] = fma(xv, sums.diagonal[j], first_group[i]);
      } else if constexpr (kSums != Sums::none) {
        // Zero lanes past the column add nothing.
        halves_tile = fma(xv, sums.diagonal[j], halves_tile);
      }
    });
    if constexpr (kSums != Sums::none && !kInRegisters) store(column + kLanes * g, halves_tile);
    x += width;
  });
  if (g > 0) {
    unrolled<D>(
        [&](auto j) { u[j * u_stride + g] = u[j * u_stride + g] + transpose_sum(column_sums[j]); });
  }
}

/// u + j·u_stride = X̃_j q̂' for the D consecutive blocks X̃_j at x + j·block_size with second
/// index c, u[J] holding rows 8J..8J+7 (zero past c), q_tiles[J] = q̂[8J..8J+8), and the blocks'
/// Hessian terms to `sums` as kSums says. K is the number of groups of c, or 0 if it exceeds
/// kMaxRegisterGroups (then D = 1); c is an int or an Index.
template <int K, int D, Sums kSums, typename Column>
[[gnu::always_inline]] inline void block_product(const double* x, Eigen::Index block_size, Column c,
                                                 const double* q, const Lanes* q_tiles, Lanes* u,
                                                 int u_stride, const SumTarget<D>& sums,
                                                 Lanes* first_group) noexcept {
  static_assert(K > 0 || D == 1);
  const int groups = K > 0 ? K : c / kLanes + 1;
  const auto width = [&](int g) { return g + 1 == groups ? c + 1 - kLanes * g : kLanes; };
  const auto add = [&](auto g) {
    add_group<D, kSums>(g, width(g), x, block_size, q, q_tiles, u, u_stride, sums, first_group);
  };
  if constexpr (K > 0) {
    unrolled<D>(
        [&](auto j) { unrolled<K>([&](auto tile) { u[j * u_stride + tile] = zero_lanes(); }); });
    unrolled<K>(add);
  } else {
    for (int tile = 0; tile < groups; ++tile) u[tile] = zero_lanes();
    add(Index<0>{});
    add(Index<1>{});
    for (int g = 2; g < groups; ++g) add(g);
  }
}

/// Lane-wise Σ x ⊙ w over `size` doubles (a whole number of tiles).
Lanes block_dot(const double* x, const double* w, Eigen::Index size) noexcept {
  Lanes acc[2] = {zero_lanes(), zero_lanes()};  // Two chains: blocks are short.
  Eigen::Index p = 0;
  for (; p + 2 * kLanes <= size; p += 2 * kLanes) {
    acc[0] = fma(load(x + p), load(w + p), acc[0]);
    acc[1] = fma(load(x + p + kLanes), load(w + p + kLanes), acc[1]);
  }
  if (p < size) acc[0] = fma(load(x + p), load(w + p), acc[0]);
  return acc[0] + acc[1];
}

/// Blocks a Hessian pass takes together (D of block_product): two where their products fit in
/// registers, so that each load and store of the Hessian halves serves two coefficient vectors.
template <int K>
constexpr int kBlocksTogether = K > 0 ? 2 : 1;

/// Registers for the q̂ tiles and the products of D blocks with K > 0 groups; scratch when K = 0.
template <int K, int D = 1>
struct Tiles {
  Lanes q[K > 0 ? K : 1];
  Lanes product[(K > 0 ? K : 1) * D];  // D = 1 when K = 0
  Lanes product_sum[K > 0 ? K : 1];
};

void set_zero(double* p, Eigen::Index size) noexcept {
  for (Eigen::Index k = 0; k < size; k += kLanes) store(p + k, zero_lanes());
}

/// destination[8t..8t+8) += Σ_{d in tile t} sum(lanes[d]) e_d for the tiles t covering
/// [first, end): one transposed sum per eight d.
void add_lane_sums(const Lanes* lanes, int first, int end, double* destination) noexcept {
  for (int d = first - first % kLanes; d < end; d += kLanes) {
    Lanes batch[kLanes];
    for (int i = 0; i < kLanes; ++i) batch[i] = lanes[d + i];
    store(destination + d, load(destination + d) + transpose_sum(batch));
  }
}

/// One c: all blocks (c, d ≥ c) into the Hessian halves; returns the end of the coefficients.
template <int K, typename Column>
[[gnu::flatten]] const double* hessian_slice(const double* x, Column c, int n, const double* q,
                                             double* halves, Eigen::Index stride,
                                             QuarticScratch& scratch) noexcept {
  // Small blocks take a few cycles each: what is summed over d stays in registers where there
  // are enough of them, so that few chains of dependent loads and stores span the blocks.
  constexpr Sums kSums = K >= 1 && K <= 3 ? Sums::halves_first_group_in_registers : Sums::halves;
  const int groups = c / kLanes + 1;
  constexpr int kD = kBlocksTogether<K>;
  Tiles<K, kD> registers;
  Lanes* q_tiles = K > 0 ? registers.q : scratch.q_tiles.data();
  Lanes* u = K > 0 ? registers.product : scratch.product.data();
  const int u_stride = K > 0 ? K : groups;
  Lanes* u_sum = K > 0 ? registers.product_sum : scratch.product_sum.data();  // Σ_d q̂_d u_cd
  for_each_index(K > 0 ? K : groups, [&](auto tile) {
    q_tiles[tile] = load(q + kLanes * tile);
    u_sum[tile] = zero_lanes();
  });
  Lanes first_group[kLanes];
  if constexpr (kSums == Sums::halves_first_group_in_registers) {
    unrolled<kLanes>([&](auto b) { first_group[b] = zero_lanes(); });
  }
  Lanes* pair_sums = scratch.pair_sums.data();  // f_cd, unreduced
  for (int d = c - c % kLanes; d < c; ++d) pair_sums[d] = zero_lanes();
  const Eigen::Index size = QuarticTileLayout::block_size(c);
  const Lanes qc = broadcast(q[c]);
  const Lanes two_qc = qc + qc;
  // 2(∇m uᵀ + u ∇mᵀ), one of each mirrored pair, and f_cd = q̂'ᵀu, for the block (c, d).
  const auto add_product_terms = [&](const Lanes* product, int d) {
    const Lanes qd = broadcast(q[d]);
    double* column_d = halves + d * stride;
    Lanes f = zero_lanes();
    for_each_index(K > 0 ? K : groups, [&](auto tile) {
      f = fma(product[tile], q_tiles[tile], f);
      u_sum[tile] = fma(product[tile], qd, u_sum[tile]);
      double* at_d = column_d + kLanes * tile;
      store(at_d, fma(product[tile], two_qc, load(at_d)));
    });
    pair_sums[d] = f;
  };
  int d = c;
  const auto blocks = [&]<int D>(Index<D>) {
    SumTarget<D> sums{halves, stride, {}, {}};
    unrolled<D>([&](auto j) {
      const Lanes qc_qd = qc * broadcast(q[d + j]);
      sums.off_diagonal[j] = qc_qd + qc_qd;
      sums.diagonal[j] = qc_qd;
    });
    block_product<K, D, kSums>(x, size, c, q, q_tiles, u, u_stride, sums, first_group);
    unrolled<D>([&](auto j) { add_product_terms(u + j * u_stride, d + j); });
    x += D * size;
    d += D;
  };
  while (d + kD <= n) blocks(Index<kD>{});
  while (d < n) blocks(Index<1>{});
  double* column_c = halves + c * stride;
  for_each_index(K > 0 ? K : groups, [&](auto tile) {
    double* at_c = column_c + kLanes * tile;
    store(at_c, load(at_c) + (u_sum[tile] + u_sum[tile]));
  });
  if constexpr (kSums == Sums::halves_first_group_in_registers) {
    unrolled<kLanes>([&](auto b) {
      if (b > c) return;
      double* column = halves + b * stride;
      store(column, load(column) + first_group[b]);
    });
  }
  // f (e_c e_dᵀ + e_d e_cᵀ): f_cd to M(d, c).
  add_lane_sums(pair_sums, c, n, column_c);
  return x;
}

/// One c: all blocks (c, d ≥ c) into the gradient; returns the end of the coefficients.
template <int K, typename Column>
[[gnu::flatten]] const double* gradient_slice(const double* x, Column c, int n, const double* q,
                                              double* gradient, QuarticScratch& scratch) noexcept {
  const int groups = c / kLanes + 1;
  Tiles<K> registers;
  Lanes* q_tiles = K > 0 ? registers.q : scratch.q_tiles.data();
  Lanes* u = K > 0 ? registers.product : scratch.product.data();
  Lanes* u_sum = K > 0 ? registers.product_sum : scratch.product_sum.data();  // Σ_d q̂_d u_cd
  for_each_index(K > 0 ? K : groups, [&](auto tile) {
    q_tiles[tile] = load(q + kLanes * tile);
    u_sum[tile] = zero_lanes();
  });
  Lanes* pair_sums = scratch.pair_sums.data();  // Σ_c q̂_c f_cd, unreduced
  const Eigen::Index size = QuarticTileLayout::block_size(c);
  const Lanes qc = broadcast(q[c]);
  Lanes slice = zero_lanes();  // Σ_d q̂_d f_cd, unreduced
  for (int d = c; d < n; ++d, x += size) {
    block_product<K, 1, Sums::none>(x, size, c, q, q_tiles, u, K > 0 ? K : groups, SumTarget<1>{},
                                    nullptr);
    const Lanes qd = broadcast(q[d]);
    Lanes f = zero_lanes();
    for_each_index(K > 0 ? K : groups, [&](auto tile) {
      f = fma(u[tile], q_tiles[tile], f);
      u_sum[tile] = fma(u[tile], qd, u_sum[tile]);
    });
    // f ∇m
    slice = fma(f, qd, slice);
    pair_sums[d] = fma(f, qc, pair_sums[d]);
  }
  gradient[c] += sum(slice);
  // Σ_d 2 m u
  const Lanes two_qc = qc + qc;
  for_each_index(K > 0 ? K : groups, [&](auto tile) {
    double* at = gradient + kLanes * tile;
    store(at, fma(u_sum[tile], two_qc, load(at)));
  });
  return x;
}

/// slice.template operator()<K>(c) with K = the number of groups of c if it is at most
/// kMaxRegisterGroups, else K = 0; c is an Index for blocks of one or two groups (then all loop
/// bounds of their blocks are constants: they are short, and branches would cost), else an int.
template <typename Slice>
const double* dispatch(int c, Slice&& slice) {
  static_assert(kMaxRegisterGroups == 8 && kLanes == 8);
  constexpr int kConstantColumns = 2 * kLanes;
  if (c < kConstantColumns) {
    const double* end = nullptr;
    unrolled<kConstantColumns>([&](auto column) {
      if (column == c) end = slice.template operator()<column / kLanes + 1>(column);
    });
    return end;
  }
  switch (c / kLanes + 1) {
    case 3:
      return slice.template operator()<3>(c);
    case 4:
      return slice.template operator()<4>(c);
    case 5:
      return slice.template operator()<5>(c);
    case 6:
      return slice.template operator()<6>(c);
    case 7:
      return slice.template operator()<7>(c);
    case 8:
      return slice.template operator()<8>(c);
    default:
      return slice.template operator()<0>(c);
  }
}

}  // namespace

void hessian_halves(const QuarticTileLayout& layout, const double* coefficients, const double* q,
                    double* halves, QuarticScratch& scratch) noexcept {
  const int n = layout.coordinates();
  const Eigen::Index stride = padded_length(n);
  set_zero(halves, stride * n);
  const double* x = coefficients;
  for (int c = 0; c < n; ++c) {
    x = dispatch(c, [&]<int K>(auto column) {
      return hessian_slice<K>(x, column, n, q, halves, stride, scratch);
    });
  }
}

void symmetrize_halves(const QuarticTileLayout& layout, const double* halves, const double* q,
                       double* stiffness, Eigen::Index stiffness_stride, double* forces,
                       QuarticScratch& scratch) noexcept {
  const int n = layout.coordinates();
  const int r = n - 1;
  const Eigen::Index stride = padded_length(n);
  const int tiles = static_cast<int>(stride / kLanes);
  Lanes* product = scratch.product.data();  // Ĥ q̂
  for (int tile = 0; tile < tiles; ++tile) product[tile] = zero_lanes();
  // Tile (row, column) of M, its columns past n zero.
  const auto load_tile = [&](int row, int column, Lanes(&tile)[kLanes]) {
    for (int j = 0; j < kLanes; ++j) {
      const int b = kLanes * column + j;
      tile[j] = b < n ? load(halves + b * stride + kLanes * row) : zero_lanes();
    }
  };
  // Tile (row, column) of Ĥ into K̃ (rows and columns below r) and Ĥ q̂.
  const auto use_tile = [&](int row, int column, const Lanes(&tile)[kLanes]) {
    const int rows = std::min(kLanes, r - kLanes * row);
    for (int j = 0; j < kLanes; ++j) {
      const int b = kLanes * column + j;
      product[row] = fma(tile[j], broadcast(q[b]), product[row]);
      if (b < r && rows > 0) {
        store_first(stiffness + b * stiffness_stride + kLanes * row, tile[j], rows);
      }
    }
  };
  for (int row = 0; row < tiles; ++row) {
    for (int column = row; column < tiles; ++column) {
      Lanes upper[kLanes], lower[kLanes];  // Tile (row, column) of M and of Mᵀ
      load_tile(row, column, upper);
      load_tile(column, row, lower);
      transpose(lower);
      for (int j = 0; j < kLanes; ++j) upper[j] = upper[j] + lower[j];
      use_tile(row, column, upper);
      if (column != row) {
        transpose(upper);
        use_tile(column, row, upper);
      }
    }
  }
  const Lanes third = broadcast(1.0 / 3.0);
  for (int tile = 0; tile * kLanes < r; ++tile) {
    store_first(forces + kLanes * tile, product[tile] * third, std::min(kLanes, r - kLanes * tile));
  }
}

void homogenized_gradient(const QuarticTileLayout& layout, const double* coefficients,
                          const double* q, double* gradient, QuarticScratch& scratch) noexcept {
  const int n = layout.coordinates();
  set_zero(gradient, padded_length(n));
  for (int d = 0; d < n; ++d) scratch.pair_sums[static_cast<std::size_t>(d)] = zero_lanes();
  const double* x = coefficients;
  for (int c = 0; c < n; ++c) {
    x = dispatch(c, [&]<int K>(auto column) {
      return gradient_slice<K>(x, column, n, q, gradient, scratch);
    });
  }
  // Σ_c q̂_c f_cd into d.
  add_lane_sums(scratch.pair_sums.data(), 0, n, gradient);
}

double homogenized_energy(const QuarticTileLayout& layout, const double* coefficients,
                          const double* q, QuarticScratch& scratch) noexcept {
  const int n = layout.coordinates();
  double* weights = scratch.weights.data();
  const double* x = coefficients;
  Lanes energy = zero_lanes();
  for (int c = 0; c < n; ++c) {
    const Eigen::Index size = QuarticTileLayout::block_size(c);
    QuarticTileLayout::pair_weights(c, q, weights);
    Lanes slice = zero_lanes();  // Σ_d q̂_d f_cd, unreduced.
    for (int d = c; d < n; ++d, x += size) {
      slice = fma(block_dot(x, weights, size), broadcast(q[d]), slice);
    }
    energy = fma(slice, broadcast(q[c]), energy);
  }
  return sum(energy);
}

}  // namespace khz::reduced::detail
