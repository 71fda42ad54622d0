#include <khz/contact/field/deformed_distance_field.hpp>
#include <khz/contact/field/isosurface.hpp>
#include <khz/contact/pointshell/repulsion_pointshell.hpp>

#include <khz/reduced/stage_progress.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <utility>

// Every entry point that promises distance()'s value bit for bit (distance_and_gradient(),
// culling_distance(), culling_distances(), nearest_proxy()) reaches it through the same source
// operations: the neighbour search's squared distances, BlendStencil's pull-backs, the grid's
// interpolation and blended_value(). The compiler inlines these into each entry point
// separately, and with contraction allowed it may fuse a·b + c in one copy and not in another
// (CPU tuning decides, e.g. Zen's avoidance of FMA chains). This file is therefore compiled with
// -ffp-contract=off (libcontact/CMakeLists.txt): each operation rounds as written, the same in
// every copy, on any CPU.

namespace khz::contact {

namespace {

constexpr int max_neighbours = DeformedFieldOptions::max_neighbours;

std::string domain_name(std::size_t d) {
  return "DeformedDistanceField: domain " + std::to_string(d);
}

/// What both constructors check first.
void check_inputs(const DeformedFieldOptions& options, const std::vector<DistanceGrid>& fields,
                  const reduced::MeshEmbedding& embedding, const Eigen::MatrixXd& basis) {
  options.validate();
  if (fields.empty()) throw Error("DeformedDistanceField: no domain fields given");
  for (std::size_t d = 0; d < fields.size(); ++d) {
    if (!fields[d].is_signed()) {
      throw Error(domain_name(d) + ": the field is unsigned (a signed field is needed)");
    }
  }
  const Eigen::Index rows = 3 * embedding.mesh().num_vertices();
  if (basis.rows() != rows || basis.cols() < 1) {
    throw Error("DeformedDistanceField: the basis is " + std::to_string(basis.rows()) + "×" +
                std::to_string(basis.cols()) + ", expected " + std::to_string(rows) +
                " rows (3 per volume-mesh vertex) and at least one column");
  }
}

/// The largest difference between neighbouring node values along an axis, per metre: bounds
/// the trilinear interpolant's partial derivatives inside the box.
double largest_axis_slope(const DistanceGrid& grid) {
  const int cells = grid.geometry().cells;
  const std::int64_t n = grid.geometry().nodes_per_axis();
  const float* v = grid.values().data();
  double largest = 0.0;
  for (int k = 0; k <= cells; ++k) {
    for (int j = 0; j <= cells; ++j) {
      const float* row = v + grid.geometry().node_index(0, j, k);
      for (int i = 0; i <= cells; ++i) {
        const double value = row[i];
        if (i < cells) largest = std::max(largest, std::abs(row[i + 1] - value));
        if (j < cells) largest = std::max(largest, std::abs(row[i + n] - value));
        if (k < cells) largest = std::max(largest, std::abs(row[i + n * n] - value));
      }
    }
  }
  return largest / grid.geometry().spacing;
}

/// Proxies on each field's zero level set, by particle repulsion with one level.
std::vector<PointMatrix> fit_proxies(const std::vector<DistanceGrid>& fields,
                                     const DeformedFieldOptions& options) {
  std::vector<PointMatrix> proxies;
  proxies.reserve(fields.size());
  for (std::size_t d = 0; d < fields.size(); ++d) {
    const TriangleMesh surface = isosurface(fields[d], 0.0);
    if (surface.num_triangles() == 0) {
      throw Error(domain_name(d) + ": the field's zero level set does not cross its grid");
    }
    RepulsionOptions repulsion;
    repulsion.first_level_points = options.proxies;
    repulsion.levels = 1;
    repulsion.seed = options.seed + d;
    repulsion.progress = options.progress;
    proxies.push_back(repulsion_pointshell(fields[d], 0.0, surface, repulsion).points);
  }
  return proxies;
}

/// The k proxies of [begin, end) nearest to x, sorted by squared distance (ties: lower index
/// first). Precondition: end − begin ≥ k.
struct Neighbours {
  std::array<double, max_neighbours> squared;
  std::array<Eigen::Index, max_neighbours> index;

  void insert(double d2, Eigen::Index i, int k) noexcept {
    int j = k - 1;
    for (; j > 0 && squared[static_cast<std::size_t>(j - 1)] > d2; --j) {
      squared[static_cast<std::size_t>(j)] = squared[static_cast<std::size_t>(j - 1)];
      index[static_cast<std::size_t>(j)] = index[static_cast<std::size_t>(j - 1)];
    }
    squared[static_cast<std::size_t>(j)] = d2;
    index[static_cast<std::size_t>(j)] = i;
  }
};

/// Read-only view of a state's arrays: positions and inverse gradients in the layouts the
/// header describes.
struct StateView {
  const double* rest;
  const double* positions;
  const double* inverse;
  Eigen::Index count;
};

/// The squared distances from x to proxies [begin, begin + size) into `d2` (a loop the compiler
/// vectorizes).
void squared_distances(const StateView& s, Eigen::Index begin, Eigen::Index size,
                       const Eigen::Vector3d& x, double* __restrict d2) noexcept {
  const double* __restrict px = s.positions + begin;
  const double* __restrict py = s.positions + s.count + begin;
  const double* __restrict pz = s.positions + 2 * s.count + begin;
  const double x0 = x.x(), x1 = x.y(), x2 = x.z();
  for (Eigen::Index b = 0; b < size; ++b) {
    const double dx = px[b] - x0, dy = py[b] - x1, dz = pz[b] - x2;
    d2[b] = dx * dx + dy * dy + dz * dz;
  }
}

/// Brute-force k nearest for domains of any size: the squared distances 64 proxies at a time,
/// then one pass keeping the k smallest by insertion (ties: lower index first).
void find_nearest_by_insertion(const StateView& s, Eigen::Index begin, Eigen::Index end, int k,
                               const Eigen::Vector3d& x, Neighbours& out) noexcept {
  for (int m = 0; m < k; ++m) {
    out.squared[static_cast<std::size_t>(m)] = std::numeric_limits<double>::infinity();
    out.index[static_cast<std::size_t>(m)] = begin + m;
  }
  constexpr Eigen::Index chunk = 64;
  alignas(64) std::array<double, chunk> d2;
  for (Eigen::Index first = begin; first < end; first += chunk) {
    const Eigen::Index size = std::min(chunk, end - first);
    squared_distances(s, first, size, x, d2.data());
    double worst = out.squared[static_cast<std::size_t>(k - 1)];
    for (Eigen::Index b = 0; b < size; ++b) {
      if (d2[static_cast<std::size_t>(b)] < worst) {
        out.insert(d2[static_cast<std::size_t>(b)], first + b, k);
        worst = out.squared[static_cast<std::size_t>(k - 1)];
      }
    }
  }
}

/// Eight 64-bit keys, one vector register (or two, or four, on narrower SIMD).
using KeyLanes = std::int64_t __attribute__((vector_size(64)));
/// Eight doubles, the keys' squared distances.
using DistanceLanes = double __attribute__((vector_size(64)));
constexpr int key_lanes = 8;

/// The packed-key searches handle domains of up to this many proxies: a proxy's offset in its
/// domain fits the key's low bits.
constexpr int packed_key_bits = 6;
constexpr Eigen::Index max_packed_proxies = Eigen::Index{1} << packed_key_bits;
constexpr std::int64_t packed_offset_mask = max_packed_proxies - 1;
/// Larger than every key: a lane with no proxy.
constexpr std::int64_t absent_key = std::numeric_limits<std::int64_t>::max();

/// A key that sorts like the squared distance d2 ≥ 0 (the IEEE bits of a non-negative double
/// order like it) and carries the proxy's offset in its low bits.
std::int64_t proxy_key(double d2, Eigen::Index offset) noexcept {
  std::int64_t bits;
  std::memcpy(&bits, &d2, sizeof bits);
  return (bits & ~packed_offset_mask) | offset;
}

/// The proxy offset a key carries.
std::size_t key_offset(std::int64_t key) noexcept {
  return static_cast<std::size_t>(key & packed_offset_mask);
}

/// keys = min(keys, keys permuted by `indices`), a constant permutation of 0…7, lane by lane.
/// Vectors go by reference: passed or returned by value they would change the function's ABI
/// between builds with and without AVX-512 (GCC's -Wpsabi).
template <int... indices>
void keep_minimum_with_permutation(KeyLanes& keys) noexcept {
#if defined(__clang__)
  const KeyLanes permuted = __builtin_shufflevector(keys, keys, indices...);
#else
  const KeyLanes permuted = __builtin_shuffle(keys, KeyLanes{indices...});
#endif
  keys = keys < permuted ? keys : permuted;
}

/// The k nearest for domains of up to 64 proxies (the thesis uses ~40), without a branch per
/// proxy: each squared distance becomes an integer key that sorts like it (IEEE bits of a
/// non-negative double) and carries the proxy's offset in its 6 lowest bits; k passes then take
/// the least key of up to 8 vectors of 8 lanes and remove it. A branching insertion mispredicts
/// on the candidates that beat the current k-th (bench_deformed_distance_field, 40 proxies,
/// k = 5: 152 ns per distance() with it, 131 without). Distances equal to within 2⁻⁴⁶ relative
/// order by index, so δ_1 ≤ … ≤ δ_k holds to that precision; larger domains take the insertion.
/// Precondition: x is finite.
void find_nearest(const StateView& s, Eigen::Index begin, Eigen::Index end, int k,
                  const Eigen::Vector3d& x, Neighbours& out) noexcept {
  constexpr int max_rows = max_packed_proxies / key_lanes;
  const Eigen::Index size = end - begin;
  if (size > max_packed_proxies) {
    find_nearest_by_insertion(s, begin, end, k, x, out);
    return;
  }
  alignas(64) std::array<double, max_packed_proxies> d2;
  squared_distances(s, begin, size, x, d2.data());
  const int rows = static_cast<int>((size + key_lanes - 1) / key_lanes);
  alignas(64) std::array<std::int64_t, max_packed_proxies> keys;
  for (Eigen::Index b = 0; b < rows * key_lanes; ++b) {
    keys[static_cast<std::size_t>(b)] =
        b < size ? proxy_key(d2[static_cast<std::size_t>(b)], b) : absent_key;
  }
  std::array<KeyLanes, max_rows> row;
  std::memcpy(row.data(), keys.data(), static_cast<std::size_t>(rows) * sizeof(KeyLanes));
  for (int m = 0; m < k; ++m) {
    KeyLanes least = row[0];
    for (int r = 1; r < rows; ++r) {
      const KeyLanes& other = row[static_cast<std::size_t>(r)];
      least = least < other ? least : other;
    }
    // The least key into every lane, by three butterflies.
    keep_minimum_with_permutation<4, 5, 6, 7, 0, 1, 2, 3>(least);
    keep_minimum_with_permutation<2, 3, 0, 1, 6, 7, 4, 5>(least);
    keep_minimum_with_permutation<1, 0, 3, 2, 5, 4, 7, 6>(least);
    for (int r = 0; r < rows; ++r) {
      KeyLanes& lane = row[static_cast<std::size_t>(r)];
      lane = lane == least ? absent_key : lane;
    }
    const std::size_t b = key_offset(least[0]);
    out.squared[static_cast<std::size_t>(m)] = d2[b];
    out.index[static_cast<std::size_t>(m)] = begin + static_cast<Eigen::Index>(b);
  }
}

/// Steps 1–3 of one domain's blend up to the rest-field lookups: the k nearest proxies, the
/// weights of eq. 3.16 (up to their common factor) and the pull-backs X_i of eq. 3.17.
struct BlendStencil {
  Neighbours neighbours;
  int lookups = 0;  // k − 1: the k-th neighbour has weight 0 and needs no lookup
  bool spread = false;
  double d_min = 0.0, d_max = 0.0;
  double inverse_sum = 0.0;  // 1 / Σ u_i
  // The first `lookups` entries of each array are set; the others are never read.
  std::array<double, max_neighbours> distance, weight;  // δ_i and u_i
  std::array<Eigen::Vector3d, max_neighbours> offset;   // x − p_i
  std::array<Eigen::Vector3d, max_neighbours> pulled;   // X_i

  /// Unset until set(): a batch keeps its stencils in an array without zeroing 10 KB of them
  /// per group of points (a tenth of a deformed field's culling time).
  BlendStencil() noexcept = default;
  BlendStencil(const StateView& s, Eigen::Index begin, Eigen::Index end, int k,
               const Eigen::Vector3d& x) noexcept {
    find_nearest(s, begin, end, k, x, neighbours);
    set_up(s, k, x);
  }
  /// With the neighbours found already (find_nearest_batch()).
  void set(const StateView& s, const Neighbours& nearest, int k,
           const Eigen::Vector3d& x) noexcept {
    neighbours = nearest;
    set_up(s, k, x);
  }

 private:
  void set_up(const StateView& s, int k, const Eigen::Vector3d& x) noexcept {
    lookups = k - 1;
    d_min = std::sqrt(neighbours.squared[0]);
    d_max = std::sqrt(neighbours.squared[static_cast<std::size_t>(lookups)]);
    // u_i = (δ_1/δ_i)(δ_k − δ_i) = δ_1 δ_k v_i: eq. 3.16's weights up to a common factor,
    // bounded by δ_k, finite at δ_1 = 0 (where proxy 1 takes weight 1, the limit), and summing
    // to at least δ_k − δ_1 > 0 whenever the distances are not all equal.
    spread = d_max > d_min;
    double weight_sum = 0.0;
    const Eigen::Index n = s.count;
    for (int m = 0; m < lookups; ++m) {
      const auto mm = static_cast<std::size_t>(m);
      distance[mm] = std::sqrt(neighbours.squared[mm]);
      const double ratio = distance[mm] > 0.0 ? d_min / distance[mm] : 1.0;
      weight[mm] = spread ? ratio * (d_max - distance[mm]) : 1.0;
      weight_sum += weight[mm];
      const Eigen::Index i = neighbours.index[mm];
      const Eigen::Vector3d r(x.x() - s.positions[i], x.y() - s.positions[n + i],
                              x.z() - s.positions[2 * n + i]);
      const double* f = s.inverse + i;  // entry (a, b) at f[(3a + b) n]
      // X_i = P_i + F_i⁻¹ (x − p_i)   (eq. 3.17)
      pulled[mm] = Eigen::Vector3d(
          s.rest[i] + f[0] * r.x() + f[n] * r.y() + f[2 * n] * r.z(),
          s.rest[n + i] + f[3 * n] * r.x() + f[4 * n] * r.y() + f[5 * n] * r.z(),
          s.rest[2 * n + i] + f[6 * n] * r.x() + f[7 * n] * r.y() + f[8 * n] * r.z());
      offset[mm] = r;
    }
    inverse_sum = 1.0 / weight_sum;
  }
};

/// Σ u_i d_i / Σ u_i over the stencil's lookups, d_i = value[i]: the one sum every entry point's
/// exact value goes through, in one order.
double blended_value(const BlendStencil& b,
                     const std::array<double, max_neighbours>& value) noexcept {
  double sum = b.weight[0] * value[0];
  for (int m = 1; m < b.lookups; ++m) {
    const auto mm = static_cast<std::size_t>(m);
    sum += b.weight[mm] * value[mm];
  }
  return sum * b.inverse_sum;
}

/// One domain's blend d = Σ w_i d_i (eq. 3.16, 3.17) and, with_gradient, its gradient; the
/// derivation of the weights' term is in the comment inside. Writes the nearest proxy.
template <bool with_gradient>
double blend(const StateView& s, const DistanceGrid& grid, Eigen::Index begin, Eigen::Index end,
             int k, const Eigen::Vector3d& x, Eigen::Index& nearest,
             Eigen::Vector3d& gradient) noexcept {
  const BlendStencil b(s, begin, end, k, x);
  nearest = b.neighbours.index[0];
  const int last = b.lookups;
  const double d_min = b.d_min, d_max = b.d_max, inverse_sum = b.inverse_sum;
  const auto& distance = b.distance;
  const auto& weight = b.weight;
  const auto& offset = b.offset;
  std::array<double, max_neighbours> value{};
  const Eigen::Index n = s.count;
  Eigen::Vector3d field_term = Eigen::Vector3d::Zero();
  for (int m = 0; m < last; ++m) {
    const auto mm = static_cast<std::size_t>(m);
    if constexpr (with_gradient) {
      const double* f = s.inverse + b.neighbours.index[mm];
      Eigen::Vector3d g;
      value[mm] = grid.distance_and_gradient(b.pulled[mm], g);
      // F_i⁻ᵀ ∇d(X_i), weighted.
      field_term.x() += weight[mm] * (f[0] * g.x() + f[3 * n] * g.y() + f[6 * n] * g.z());
      field_term.y() += weight[mm] * (f[n] * g.x() + f[4 * n] * g.y() + f[7 * n] * g.z());
      field_term.z() += weight[mm] * (f[2 * n] * g.x() + f[5 * n] * g.y() + f[8 * n] * g.z());
    } else {
      value[mm] = grid.distance(b.pulled[mm]);
    }
  }
  const double result = blended_value(b, value);
  if constexpr (with_gradient) {
    gradient = inverse_sum * field_term;
    if (b.spread) {
      // With v_i = 1/δ_i − 1/δ_k, V = Σ v_i, w_i = v_i/V and D the result:
      //   Σ_i d_i ∇w_i = Σ_i (d_i − D) ∇v_i / V,  ∇v_i = −r_i/δ_i³ + r_k/δ_k³  (r_i = x − p_i),
      // and ∇v_k = 0. In terms of u_i = δ_1 δ_k v_i (U = Σ u_i):
      //   ∇v_i / V = (−δ_1 δ_k r_i/δ_i³ + δ_1 r_k/δ_k²) / U.
      // At δ_i = 0 (x on a proxy) the term is left out: d is not differentiable there.
      Eigen::Vector3d weight_term = Eigen::Vector3d::Zero();
      double excess_sum = 0.0;
      for (int m = 0; m < last; ++m) {
        const auto mm = static_cast<std::size_t>(m);
        const double excess = value[mm] - result;
        excess_sum += excess;
        if (distance[mm] > 0.0) {
          weight_term -= (excess * (d_min / distance[mm]) * (d_max / distance[mm]) / distance[mm]) *
                         offset[mm];
        }
      }
      const Eigen::Index kth = b.neighbours.index[static_cast<std::size_t>(last)];
      const Eigen::Vector3d r_k(x.x() - s.positions[kth], x.y() - s.positions[n + kth],
                                x.z() - s.positions[2 * n + kth]);
      weight_term += (excess_sum * d_min / (d_max * d_max)) * r_k;
      gradient += inverse_sum * weight_term;
    }
  }
  return result;
}

}  // namespace

void DeformedFieldOptions::validate() const {
  const std::string where = "DeformedFieldOptions: ";
  if (neighbours < 2 || neighbours > max_neighbours) {
    throw Error(where + "neighbours " + std::to_string(neighbours) + " is not in [2, " +
                std::to_string(max_neighbours) + "]");
  }
  if (proxies < neighbours) {
    throw Error(where + "proxies " + std::to_string(proxies) + " is below neighbours (" +
                std::to_string(neighbours) + ")");
  }
}

DeformedDistanceField::DeformedDistanceField(std::vector<DistanceGrid> fields,
                                             const reduced::MeshEmbedding& embedding,
                                             const Eigen::MatrixXd& basis,
                                             const DeformedFieldOptions& options)
    : m_fields(std::move(fields)), m_neighbours(options.neighbours) {
  check_inputs(options, m_fields, embedding, basis);
  initialize(fit_proxies(m_fields, options), embedding, basis, options.progress);
}

DeformedDistanceField::DeformedDistanceField(std::vector<DistanceGrid> fields,
                                             const std::vector<PointMatrix>& proxies,
                                             const reduced::MeshEmbedding& embedding,
                                             const Eigen::MatrixXd& basis,
                                             const DeformedFieldOptions& options)
    : m_fields(std::move(fields)), m_neighbours(options.neighbours) {
  check_inputs(options, m_fields, embedding, basis);
  if (proxies.size() != m_fields.size()) {
    throw Error("DeformedDistanceField: " + std::to_string(proxies.size()) + " proxy sets for " +
                std::to_string(m_fields.size()) + " fields");
  }
  for (std::size_t d = 0; d < proxies.size(); ++d) {
    if (proxies[d].rows() < m_neighbours) {
      throw Error(domain_name(d) + ": " + std::to_string(proxies[d].rows()) +
                  " proxies, fewer than neighbours (" + std::to_string(m_neighbours) + ")");
    }
    for (Eigen::Index i = 0; i < proxies[d].rows(); ++i) {
      if (!proxies[d].row(i).allFinite()) {
        throw Error(domain_name(d) + ": proxy " + std::to_string(i) + " is not finite");
      }
    }
  }
  initialize(proxies, embedding, basis, options.progress);
}

void DeformedDistanceField::initialize(const std::vector<PointMatrix>& proxies,
                                       const reduced::MeshEmbedding& embedding,
                                       const Eigen::MatrixXd& basis,
                                       const ProgressCallback& progress) {
  for (const DistanceGrid& grid : m_fields) m_slopes.push_back(largest_axis_slope(grid));
  m_dimension = basis.cols();
  for (Eigen::Index v = 0; 3 * v < basis.rows(); ++v) {
    m_displacement_bound = std::max(m_displacement_bound, basis.middleRows(3 * v, 3).norm());
  }
  Eigen::Index count = 0;
  for (const PointMatrix& points : proxies) {
    count += points.rows();
    m_domain_ends.push_back(count);
  }
  const Eigen::Index r = m_dimension;
  m_rest.resize(3 * count);
  m_displacement.resize(3 * count, r);
  m_gradient.resize(9 * count, r);
  reduced::StageProgress stage(progress, "proxy modes", count);
  Eigen::Index i = 0;
  for (const PointMatrix& points : proxies) {
    for (Eigen::Index p = 0; p < points.rows(); ++p, ++i) {
      const Eigen::Vector3d rest = points.row(p).transpose();
      const reduced::PointModes modes = embedding.modes(embedding.locate(rest), basis);
      for (int a = 0; a < 3; ++a) {
        m_rest[a * count + i] = rest[a];
        m_displacement.row(a * count + i) = modes.displacement.row(a);
        for (int b = 0; b < 3; ++b) {
          for (Eigen::Index j = 0; j < r; ++j) {
            m_gradient((3 * a + b) * count + i, j) =
                modes.gradient[static_cast<std::size_t>(j)](a, b);
          }
        }
      }
      stage.advance();
    }
  }
  stage.finish();
}

Eigen::Vector3d DeformedDistanceField::rest_position(Eigen::Index i) const noexcept {
  const Eigen::Index n = num_proxies();
  assert(i >= 0 && i < n);
  return {m_rest[i], m_rest[n + i], m_rest[2 * n + i]};
}

Eigen::Matrix<double, 3, Eigen::Dynamic> DeformedDistanceField::displacement_modes(
    Eigen::Index i) const {
  const Eigen::Index n = num_proxies();
  assert(i >= 0 && i < n);
  Eigen::Matrix<double, 3, Eigen::Dynamic> modes(3, m_dimension);
  for (int a = 0; a < 3; ++a) modes.row(a) = m_displacement.row(a * n + i);
  return modes;
}

Eigen::Matrix3d DeformedDistanceField::gradient_mode(Eigen::Index i,
                                                     Eigen::Index j) const noexcept {
  const Eigen::Index n = num_proxies();
  assert(i >= 0 && i < n && j >= 0 && j < m_dimension);
  Eigen::Matrix3d mode;
  for (int a = 0; a < 3; ++a) {
    for (int b = 0; b < 3; ++b) mode(a, b) = m_gradient((3 * a + b) * n + i, j);
  }
  return mode;
}

DeformedFieldState::DeformedFieldState(const DeformedDistanceField& field)
    : m_field(&field),
      m_count(field.num_proxies()),
      m_positions(field.rest_positions()),
      m_inverse(Eigen::VectorXd::Zero(9 * m_count)),
      m_next_positions(3 * m_count),
      m_next_inverse(9 * m_count),
      m_gradient(9 * m_count),
      m_q(Eigen::VectorXd::Zero(field.dimension())) {
  for (int a = 0; a < 3; ++a) m_inverse.segment(4 * a * m_count, m_count).setOnes();
}

bool DeformedFieldState::update(const Eigen::Ref<const Eigen::VectorXd>& q) noexcept {
  const DeformedDistanceField& field = *m_field;
  if (q.size() != field.dimension() || !q.allFinite()) return false;
  m_next_positions = field.rest_positions();
  m_next_positions.noalias() += field.displacement_matrix() * q;
  m_gradient.noalias() = field.gradient_matrix() * q;
  const Eigen::Index n = m_count;
  const double* g = m_gradient.data();
  double* inv = m_next_inverse.data();
  int valid = 1;  // bitwise ands on an int: no branch per proxy
  for (Eigen::Index i = 0; i < n; ++i) {
    // F_i = I + Σ_j F_ij q_j, inverted by cofactors.
    const double f00 = 1.0 + g[i], f01 = g[n + i], f02 = g[2 * n + i];
    const double f10 = g[3 * n + i], f11 = 1.0 + g[4 * n + i], f12 = g[5 * n + i];
    const double f20 = g[6 * n + i], f21 = g[7 * n + i], f22 = 1.0 + g[8 * n + i];
    const double c00 = f11 * f22 - f12 * f21;
    const double c01 = f12 * f20 - f10 * f22;
    const double c02 = f10 * f21 - f11 * f20;
    const double det = f00 * c00 + f01 * c01 + f02 * c02;
    // Also false for NaN and for an overflow to infinity.
    valid &= static_cast<int>(det > DeformedFieldState::min_determinant) &
             static_cast<int>(det < std::numeric_limits<double>::infinity());
    const double s = 1.0 / det;
    inv[i] = c00 * s;
    inv[n + i] = (f02 * f21 - f01 * f22) * s;
    inv[2 * n + i] = (f01 * f12 - f02 * f11) * s;
    inv[3 * n + i] = c01 * s;
    inv[4 * n + i] = (f00 * f22 - f02 * f20) * s;
    inv[5 * n + i] = (f02 * f10 - f00 * f12) * s;
    inv[6 * n + i] = c02 * s;
    inv[7 * n + i] = (f01 * f20 - f00 * f21) * s;
    inv[8 * n + i] = (f00 * f11 - f01 * f10) * s;
  }
  if (valid == 0 || !m_next_positions.allFinite() || !m_next_inverse.allFinite()) return false;
  m_positions.swap(m_next_positions);
  m_inverse.swap(m_next_inverse);
  m_q = q;
  return true;
}

namespace {

/// One domain's blend if it is at most `threshold`; otherwise a lower bound of it above
/// `threshold`, from the nearest proxy's lookup alone when that suffices. Inside the box the
/// trilinear field changes by at most `slope` per metre along each axis (its derivative along an
/// axis is a weighted average of the grid's node differences along that axis), so
/// d_i ≥ d_1 − slope ‖X_i − X_1‖₁ and Σ w_i d_i ≥ d_1 − slope Σ w_i ‖X_i − X_1‖₁ when every X_i
/// lies in the box (convex, so the segments do too). The pull-backs agree closely wherever the
/// deformation is smooth, so most culled points need one lookup instead of k − 1.
double blend_above(const BlendStencil& b, const DistanceGrid& grid, double slope,
                   double threshold) noexcept {
  const double first = grid.distance(b.pulled[0]);
  bool inside = grid.contains(b.pulled[0]);
  double spread = 0.0, farthest = 0.0;
  for (int m = 1; m < b.lookups; ++m) {
    const auto mm = static_cast<std::size_t>(m);
    inside = inside && grid.contains(b.pulled[mm]);
    const double apart = (b.pulled[mm] - b.pulled[0]).cwiseAbs().sum();
    spread += b.weight[mm] * apart;
    farthest = std::max(farthest, apart);
  }
  // Less the rounding of the exact blend (a weighted mean of values no larger in magnitude than
  // |d_1| + slope · farthest) and of each value's interpolation (from corners within slope · 3h
  // of it), so that the bound never exceeds the value distance() computes. Without the second
  // term the bound came out 20 ulps above the value in a clang build for the x86-64 baseline.
  const double corners = slope * 3.0 * grid.geometry().spacing;
  const double rounding = 32.0 * std::numeric_limits<double>::epsilon() *
                          (std::abs(first) + slope * farthest + corners);
  const double bound = first - slope * spread * b.inverse_sum - rounding;
  if (inside && bound > threshold) return bound;
  // The exact blend, through blend()'s sum, so that the value is the same bit for bit.
  std::array<double, max_neighbours> value{};
  value[0] = first;
  for (int m = 1; m < b.lookups; ++m) {
    const auto mm = static_cast<std::size_t>(m);
    value[mm] = grid.distance(b.pulled[mm]);
  }
  return blended_value(b, value);
}

/// k nearest proxies of [begin, end) for up to 8 points at once, each point in one lane of the
/// packed keys of find_nearest(): every proxy's key row is inserted into k sorted rows by
/// compare-exchange, branch-free and with no pass waiting for the previous one's horizontal
/// minimum. A proxy's squared distances to the 8 points are computed in one row of lanes, so its
/// keys need no gathering from per-point arrays (gathered lane by lane they took a fifth of the
/// culling time). Each lane's squared distance is find_nearest()'s (the same operations in the
/// same order), so the same keys give the same neighbours in the same order.
/// Preconditions: end − begin ≤ 64, 1 ≤ count ≤ 8, every point finite.
void find_nearest_batch(const StateView& s, Eigen::Index begin, Eigen::Index end, int k,
                        const Eigen::Vector3d* x, int count, Neighbours* out) noexcept {
  const Eigen::Index size = end - begin;
  DistanceLanes point_x{}, point_y{}, point_z{};
  KeyLanes no_point{};  // all ones in the lanes without a point
  for (int l = 0; l < key_lanes; ++l) {
    const bool used = l < count;
    point_x[l] = used ? x[l].x() : 0.0;
    point_y[l] = used ? x[l].y() : 0.0;
    point_z[l] = used ? x[l].z() : 0.0;
    no_point[l] = used ? 0 : -1;
  }
  const double* __restrict px = s.positions + begin;
  const double* __restrict py = s.positions + s.count + begin;
  const double* __restrict pz = s.positions + 2 * s.count + begin;
  std::array<DistanceLanes, max_packed_proxies> d2;
  std::array<KeyLanes, max_neighbours> best;
  for (int m = 0; m < k; ++m) best[static_cast<std::size_t>(m)] = KeyLanes{} + absent_key;
  for (Eigen::Index b = 0; b < size; ++b) {
    const auto bb = static_cast<std::size_t>(b);
    const DistanceLanes dx = px[b] - point_x, dy = py[b] - point_y, dz = pz[b] - point_z;
    d2[bb] = dx * dx + dy * dy + dz * dz;
    KeyLanes bits;
    std::memcpy(&bits, &d2[bb], sizeof bits);
    KeyLanes row = (bits & ~packed_offset_mask) | b;
    row = no_point != 0 ? KeyLanes{} + absent_key : row;
    for (int m = 0; m < k; ++m) {
      KeyLanes& kept = best[static_cast<std::size_t>(m)];
      const KeyLanes lower = kept < row ? kept : row;
      row = kept < row ? row : kept;
      kept = lower;
    }
  }
  for (int l = 0; l < count; ++l) {
    for (int m = 0; m < k; ++m) {
      const std::size_t b = key_offset(best[static_cast<std::size_t>(m)][l]);
      out[l].squared[static_cast<std::size_t>(m)] = d2[b][l];
      out[l].index[static_cast<std::size_t>(m)] = begin + static_cast<Eigen::Index>(b);
    }
  }
}

/// The minimum over the domains of blend<with_gradient>(); `nearest` gets the minimizing
/// domain's nearest proxy.
template <bool with_gradient>
double evaluate(const DeformedDistanceField& field, const StateView& s, const Eigen::Vector3d& x,
                Eigen::Index& nearest, Eigen::Vector3d& gradient) noexcept {
  if (!x.allFinite()) {
    gradient.setConstant(std::numeric_limits<double>::quiet_NaN());
    return std::numeric_limits<double>::quiet_NaN();
  }
  const int k = field.neighbours();
  double best = blend<with_gradient>(s, field.field(0), field.domain_begin(0), field.domain_end(0),
                                     k, x, nearest, gradient);
  for (Eigen::Index d = 1; d < field.num_domains(); ++d) {
    Eigen::Index candidate_nearest = -1;
    Eigen::Vector3d candidate_gradient;
    const double value =
        blend<with_gradient>(s, field.field(d), field.domain_begin(d), field.domain_end(d), k, x,
                             candidate_nearest, candidate_gradient);
    if (value < best) {
      best = value;
      nearest = candidate_nearest;
      if constexpr (with_gradient) gradient = candidate_gradient;
    }
  }
  return best;
}

}  // namespace

double DeformedFieldState::cell_size() const noexcept {
  double finest = m_field->field(0).cell_size();
  for (Eigen::Index d = 1; d < m_field->num_domains(); ++d) {
    finest = std::min(finest, m_field->field(d).cell_size());
  }
  return finest;
}

double DeformedFieldState::distance(const Eigen::Vector3d& x) const noexcept {
  const StateView view{m_field->rest_positions().data(), m_positions.data(), m_inverse.data(),
                       m_count};
  Eigen::Index nearest = -1;
  Eigen::Vector3d unused;
  return evaluate<false>(*m_field, view, x, nearest, unused);
}

double DeformedFieldState::distance_and_gradient(const Eigen::Vector3d& x,
                                                 Eigen::Vector3d& gradient) const noexcept {
  const StateView view{m_field->rest_positions().data(), m_positions.data(), m_inverse.data(),
                       m_count};
  Eigen::Index nearest = -1;
  return evaluate<true>(*m_field, view, x, nearest, gradient);
}

double DeformedFieldState::culling_distance(const Eigen::Vector3d& x,
                                            double threshold) const noexcept {
  if (!x.allFinite()) return std::numeric_limits<double>::quiet_NaN();
  const StateView view{m_field->rest_positions().data(), m_positions.data(), m_inverse.data(),
                       m_count};
  // Each domain's value is exact when at most the threshold and a bound above it otherwise, so
  // their minimum is the exact minimum when that is at most the threshold.
  const DeformedDistanceField& field = *m_field;
  double best = std::numeric_limits<double>::infinity();
  for (Eigen::Index d = 0; d < field.num_domains(); ++d) {
    const BlendStencil stencil(view, field.domain_begin(d), field.domain_end(d), field.neighbours(),
                               x);
    best = std::min(best, blend_above(stencil, field.field(d), field.field_slope(d), threshold));
  }
  return best;
}

void DeformedFieldState::culling_distances(std::span<const Eigen::Vector3d> x,
                                           std::span<const double> thresholds,
                                           std::span<double> out) const noexcept {
  assert(thresholds.size() == x.size() && out.size() == x.size());
  cull(x.first(std::min({x.size(), thresholds.size(), out.size()})), thresholds, out, nullptr);
}

void DeformedFieldState::culling_distances(std::span<const Eigen::Vector3d> x,
                                           std::span<const double> thresholds,
                                           std::span<double> out,
                                           std::span<Eigen::Index> nearest) const noexcept {
  assert(thresholds.size() == x.size() && out.size() == x.size() && nearest.size() == x.size());
  cull(x.first(std::min({x.size(), thresholds.size(), out.size(), nearest.size()})), thresholds,
       out, nearest.data());
}

void DeformedFieldState::cull(std::span<const Eigen::Vector3d> x,
                              std::span<const double> thresholds, std::span<double> out,
                              Eigen::Index* nearest_out) const noexcept {
  const std::size_t count = x.size();
  const DeformedDistanceField& field = *m_field;
  const StateView view{field.rest_positions().data(), m_positions.data(), m_inverse.data(),
                       m_count};
  const int k = field.neighbours();
  constexpr int lanes = key_lanes;
  for (std::size_t first = 0; first < count; first += lanes) {
    // The group's finite points; the others are NaN, as in culling_distance().
    std::array<Eigen::Vector3d, lanes> points;
    std::array<std::size_t, lanes> slot;
    int used = 0;
    for (std::size_t i = first; i < std::min<std::size_t>(first + lanes, count); ++i) {
      const bool finite = x[i].allFinite();
      out[i] = finite ? std::numeric_limits<double>::infinity()
                      : std::numeric_limits<double>::quiet_NaN();
      if (nearest_out != nullptr) nearest_out[i] = -1;
      if (!finite) continue;
      points[static_cast<std::size_t>(used)] = x[i];
      slot[static_cast<std::size_t>(used++)] = i;
    }
    if (used == 0) continue;
    for (Eigen::Index d = 0; d < field.num_domains(); ++d) {
      const Eigen::Index begin = field.domain_begin(d), end = field.domain_end(d);
      std::array<Neighbours, lanes> nearest;
      if (end - begin <= max_packed_proxies) {
        find_nearest_batch(view, begin, end, k, points.data(), used, nearest.data());
      } else {
        for (int l = 0; l < used; ++l) {
          find_nearest(view, begin, end, k, points[static_cast<std::size_t>(l)],
                       nearest[static_cast<std::size_t>(l)]);
        }
      }
      // Every stencil first, each first lookup requested, so that the group's cache misses
      // overlap; then the blends.
      const DistanceGrid& grid = field.field(d);
      std::array<BlendStencil, lanes> stencils;
      for (int l = 0; l < used; ++l) {
        const auto u = static_cast<std::size_t>(l);
        stencils[u].set(view, nearest[u], k, points[u]);
        grid.prefetch(stencils[u].pulled[0]);
      }
      for (int l = 0; l < used; ++l) {
        const auto u = static_cast<std::size_t>(l);
        const std::size_t i = slot[u];
        // As evaluate(): the first domain giving the least value, and its nearest proxy.
        const double value = blend_above(stencils[u], grid, field.field_slope(d), thresholds[i]);
        if (!(value < out[i])) continue;
        out[i] = value;
        if (nearest_out != nullptr) nearest_out[i] = stencils[u].neighbours.index[0];
      }
    }
  }
}

Eigen::Index DeformedFieldState::nearest_proxy(const Eigen::Vector3d& x) const noexcept {
  if (!x.allFinite()) return -1;
  const StateView view{m_field->rest_positions().data(), m_positions.data(), m_inverse.data(),
                       m_count};
  if (m_field->num_domains() == 1) {
    Neighbours nearest;
    find_nearest(view, 0, m_count, 1, x, nearest);
    return nearest.index[0];
  }
  Eigen::Index nearest = -1;
  Eigen::Vector3d unused;
  evaluate<false>(*m_field, view, x, nearest, unused);
  return nearest;
}

void DeformedFieldState::add_reduced_force(const Eigen::Vector3d& x, const Eigen::Vector3d& force,
                                           Eigen::Ref<Eigen::VectorXd> reduced) const noexcept {
  add_proxy_reduced_force(nearest_proxy(x), force, reduced);
}

void DeformedFieldState::add_proxy_reduced_force(
    Eigen::Index proxy, const Eigen::Vector3d& force,
    Eigen::Ref<Eigen::VectorXd> reduced) const noexcept {
  assert(reduced.size() == dimension() && proxy >= -1 && proxy < m_count);
  if (reduced.size() != dimension() || proxy < 0 || proxy >= m_count) return;
  // U_iᵀ f = Σ_a f_a · (row a of U_i).
  const Eigen::MatrixXd& modes = m_field->displacement_matrix();
  for (int a = 0; a < 3; ++a) reduced += force[a] * modes.row(a * m_count + proxy).transpose();
}

Eigen::Vector3d DeformedFieldState::position(Eigen::Index i) const noexcept {
  assert(i >= 0 && i < m_count);
  return {m_positions[i], m_positions[m_count + i], m_positions[2 * m_count + i]};
}

Eigen::Matrix3d DeformedFieldState::inverse_gradient(Eigen::Index i) const noexcept {
  assert(i >= 0 && i < m_count);
  Eigen::Matrix3d inverse;
  for (int a = 0; a < 3; ++a) {
    for (int b = 0; b < 3; ++b) inverse(a, b) = m_inverse[(3 * a + b) * m_count + i];
  }
  return inverse;
}

}  // namespace khz::contact
