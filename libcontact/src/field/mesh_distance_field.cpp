#include <khz/contact/field/mesh_distance_field.hpp>
#include <khz/reduced/stage_progress.hpp>
#include <khz/reduced/worker_threads.hpp>

#include <omp.h>

#include "field/distance_field_regions.hpp"
#include "field/mesh_distance_bvh.hpp"
#include "field/mesh_distance_pseudonormals.hpp"

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

// How the field is computed (thesis §3.11 leaves it open):
//
// 1. Band. Nodes within exact_band spacings of the mesh get their exact closest triangle from
//    the bounding-volume hierarchy, and, for a signed field, their side from the pseudonormal
//    of the closest feature. Blocks of 8³ nodes farther than the band from the mesh are skipped
//    after one search from their centre. If the mesh reaches outside the grid's box, the nodes
//    on the box's faces are made exact too (a closest point outside the box is seen through
//    them); if no node is exact at all, the corners are.
// 2. Fill. Closest triangles spread from the exact nodes to all others by six cone sweeps, one
//    per axis direction: plane by plane, each node keeps the closest of its own candidate and
//    those of the 3×3 nodes behind it in the previous plane. The nodes reached from an exact
//    node this way surround every ray leaving it at up to 45° from the sweep axis, so the
//    straight segment from a node to its closest point is followed by one of the six sweeps.
//    Nodes of a plane are independent, so each plane is shared among threads, and the result
//    does not depend on the thread count. A node's value is the exact distance to the triangle
//    it ends with: never below the true distance, above it where that triangle's region of
//    closest points is too thin for the grid to carry it (measured in the tests and
//    bench_distance_field: at most 0.04 spacings).
// 3. Sides (signed fields). A node beyond the band is more than √3 spacings from the mesh, so
//    the segment to any of its 26 neighbours cannot cross the surface, and the sweeps hand each
//    such node the side of the neighbour it first got a candidate from. The 6-connected regions
//    of such nodes then each take the side most of their nodes got (BandRegions), so a band
//    node signed wrongly next to a self-intersection cannot spread a streak.
//
// A sweep offers a node only the neighbours that changed since an earlier sweep last offered
// them (see Sweep): a neighbour's unchanged triangle was already weighed, and the node's own
// triangle has only become closer since, so weighing it again cannot change anything. This
// keeps the result that of offering all nine, with a fifth fewer distances computed (bunny00.off
// at 256³: 177 M instead of 215 M; most nodes change in the first two sweeps, so later sweeps
// still re-offer most edge and corner neighbours).
//
// While the field is computed, each node's 4 bytes (the storage of its final float value) hold
// a slot word: the index of its closest triangle so far, the last sweep that changed it and two
// flags, so the computation needs no memory per node beyond its result.

namespace khz::contact {
namespace {

constexpr std::string_view stage_name = "distance field";
/// Edge of the node blocks the band search culls at once (nodes).
constexpr int block_nodes = 8;
/// Grid planes per progress unit in the band search and the final passes.
constexpr int planes_per_unit = 8;
/// Sweep steps per call of cone_sweep() (and progress unit): each call costs the threads two
/// meetings, and its phase 2 leaves part of them idle for a fraction (threads − 1)·steps/n of
/// the work; n/(8·threads) steps keep that under 1/8, within these bounds.
constexpr int min_sweep_steps = 4;
constexpr int max_sweep_steps = 64;
/// Nodes per plane from which the passes run in parallel. The sweeps meet at a barrier after
/// every plane; below about 1 ms of work per plane (and per pass unit) the barriers cost more
/// than they save, far more when other processes take the cores.
constexpr std::int64_t min_parallel_plane = 96 * 96;

constexpr std::uint32_t triangle_bits = (std::uint32_t{1} << 27) - 1;
constexpr std::uint32_t unknown_triangle = triangle_bits;  ///< no candidate yet
/// Bits 27–29: the last sweep (1–6, 0 = none) that changed the node's triangle.
constexpr int changed_shift = 27;
constexpr std::uint32_t changed_bits = std::uint32_t{7} << changed_shift;
constexpr std::uint32_t exact_bit = std::uint32_t{1} << 30;   ///< band node: final triangle
constexpr std::uint32_t inside_bit = std::uint32_t{1} << 31;  ///< node is inside the mesh
/// Most triangles a slot word can name.
constexpr Eigen::Index max_triangles = unknown_triangle;
/// Largest cells per axis (140 TB of values): keeps the per-plane counts within int.
constexpr int max_cells = 1 << 15;
/// Smallest exact band: nodes beyond it take their side from neighbours up to a cell diagonal
/// away.
const double min_exact_band = std::sqrt(3.0);

/// The node values seen as slot words (bytes copied, so no float is ever formed from them).
class SlotWords {
 public:
  explicit SlotWords(std::vector<float>& values) noexcept : m_data(values.data()) {}
  std::uint32_t load(std::int64_t node) const noexcept {
    std::uint32_t word;
    std::memcpy(&word, m_data + node, sizeof(word));
    return word;
  }
  void store(std::int64_t node, std::uint32_t word) const noexcept {
    std::memcpy(m_data + node, &word, sizeof(word));
  }

 private:
  float* m_data;
};

int ceil_div(int a, int b) { return (a + b - 1) / b; }
double square(double x) { return x * x; }

Eigen::AlignedBox3d vertex_bounds(const TriangleMesh& mesh) {
  Eigen::AlignedBox3d bounds;
  bounds.setEmpty();
  for (Eigen::Index v = 0; v < mesh.num_vertices(); ++v)
    bounds.extend(mesh.vertices.row(v).transpose());
  return bounds;
}

/// The grid the options ask for, after checking the options and the memory budget.
GridGeometry field_geometry(const std::string& caller, const TriangleMesh& mesh,
                            const DistanceFieldOptions& options) {
  if (!(options.exact_band >= min_exact_band)) {
    throw Error(caller + ": exact_band must be at least √3 ≈ 1.732 cell spacings, got " +
                std::to_string(options.exact_band));
  }
  if (options.memory_budget_bytes <= 0) {
    throw Error(caller + ": memory_budget_bytes must be positive, got " +
                std::to_string(options.memory_budget_bytes));
  }
  GridGeometry geometry;
  if (options.geometry) {
    geometry = *options.geometry;
    geometry.validate();
  } else {
    geometry = GridGeometry::cube_around(vertex_bounds(mesh), options.box_expansion, options.cells);
  }
  // In double: the node count can overflow before the budget refuses it.
  const double nodes_per_axis = static_cast<double>(geometry.cells) + 1.0;
  const double bytes = sizeof(float) * nodes_per_axis * nodes_per_axis * nodes_per_axis;
  if (geometry.cells > max_cells || bytes > static_cast<double>(options.memory_budget_bytes)) {
    throw Error(caller + ": a grid of " + std::to_string(geometry.cells) + "³ cells needs " +
                std::to_string(static_cast<long long>(bytes)) +
                " bytes of node values, more than the memory budget of " +
                std::to_string(options.memory_budget_bytes) +
                " bytes (DistanceFieldOptions::memory_budget_bytes)");
  }
  return geometry;
}

/// The field under construction: search structures, the grid and its slot words.
class FieldBuilder {
 public:
  FieldBuilder(const TriangleMesh& mesh, const GridGeometry& geometry, double exact_band,
               bool is_signed, std::vector<float>& values)
      : m_geometry(geometry),
        m_last(geometry.cells),
        m_band(exact_band * geometry.spacing),
        m_signed(is_signed),
        m_parallel(std::int64_t{geometry.nodes_per_axis()} * geometry.nodes_per_axis() >=
                   min_parallel_plane),
        m_bvh(mesh.vertices, mesh.triangles),
        m_slots(values),
        m_regions(geometry.nodes_per_axis()) {
    if (is_signed) m_normals = detail::compute_pseudonormals(mesh.vertices, mesh.triangles);
    m_prepared.reserve(m_bvh.triangles().size());
    for (const detail::BvhTriangle& t : m_bvh.triangles()) {
      m_prepared.emplace_back(t.a, t.b, t.c, t.degenerate);
    }
    for (std::int64_t node = 0; node < geometry.node_count(); ++node) {
      m_slots.store(node, unknown_triangle);
    }
  }

  int block_layers() const { return ceil_div(m_last + 1, block_nodes); }

  /// Step 1 for the blocks of layer `layer` (nodes k in [8·layer, 8·layer + 8)); returns the
  /// number of nodes it made exact.
  std::int64_t band_layer(int layer) {
    const int blocks = block_layers();
    std::int64_t exact = 0;
#pragma omp parallel for num_threads(reduced::worker_threads()) schedule(dynamic, 1) reduction(+ : exact) if (m_parallel)
    for (int b = 0; b < blocks * blocks; ++b) {
      const Eigen::Vector3i lower(b % blocks * block_nodes, b / blocks * block_nodes,
                                  layer * block_nodes);
      const Eigen::Vector3i upper =
          (lower + Eigen::Vector3i::Constant(block_nodes - 1)).cwiseMin(m_last);
      const Eigen::Vector3d centre =
          m_geometry.origin + 0.5 * m_geometry.spacing * (lower + upper).cast<double>();
      const double radius = 0.5 * m_geometry.spacing * (upper - lower).cast<double>().norm();
      detail::BvhHit hit;
      if (!m_bvh.closest(centre, square(m_band + radius), -1, hit)) continue;
      int hint = hit.slot;  // neighbouring nodes have nearby closest triangles
      for (int k = lower.z(); k <= upper.z(); ++k) {
        for (int j = lower.y(); j <= upper.y(); ++j) {
          for (int i = lower.x(); i <= upper.x(); ++i) {
            if (make_exact(i, j, k, square(m_band), hint, hit)) {
              hint = hit.slot;
              ++exact;
            }
          }
        }
      }
    }
    return exact;
  }

  /// Makes every node on the grid's faces in planes k ∈ [first, end) exact. The sweeps carry only
  /// triangles some exact node has; when the mesh reaches outside the box, a node's closest point
  /// can lie outside, and the segment to it leaves the box through a face, so the face's nodes must
  /// know it.
  void seed_boundary(int first, int end) {
    const int n = m_last + 1;
#pragma omp parallel for num_threads(reduced::worker_threads()) schedule(dynamic, 1) if (m_parallel)
    for (int row = first * n; row < end * n; ++row) {
      const int j = row % n, k = row / n;
      const bool face = j == 0 || j == m_last || k == 0 || k == m_last;
      int hint = -1;
      for (int i = 0; i <= m_last; i += face ? 1 : m_last) {
        if ((m_slots.load(m_geometry.node_index(i, j, k)) & exact_bit) != 0) continue;
        detail::BvhHit hit;
        if (make_exact(i, j, k, std::numeric_limits<double>::infinity(), hint, hit)) {
          hint = hit.slot;
        }
      }
    }
  }

  /// Makes the grid's corners exact: the seeds of the sweeps when no node is near the mesh.
  void seed_corners() {
    for (int corner = 0; corner < 8; ++corner) {
      detail::BvhHit hit;
      make_exact(corner & 1 ? m_last : 0, corner & 2 ? m_last : 0, corner & 4 ? m_last : 0,
                 std::numeric_limits<double>::infinity(), -1, hit);
    }
  }

  /// Step 2: steps [first, end) of cone sweep `sweep` (1–6: +z, −z, +y, −y, +x, −x). Step t ≥ 1
  /// updates plane t (or m_last − t going down) from the plane before it, row by row (rows run
  /// along the plane's axis of smallest stride).
  ///
  /// A row depends only on the three rows around it in the previous plane, so threads need not
  /// meet after every plane: each thread takes a band of rows and, in phase 1, updates a
  /// trapezoid of them, one row narrower at each inner edge per step; in phase 2, threads fill
  /// the widening gaps between neighbouring trapezoids. Both phases read only rows already
  /// final, so the result is that of the plane-by-plane order, with two barriers per call
  /// instead of one per plane (which lose much time when other processes take the cores).
  void cone_sweep(int number, int first, int end) {
    const Sweep sweep(*this, number);
    const int steps = end - first;
    const int n = m_last + 1;
    const auto plane_of = [&](int t) { return sweep.direction() > 0 ? t : m_last - t; };
    if (!m_parallel) {
      for (int t = first; t < end; ++t) {
        for (int v = 0; v < n; ++v) sweep.row(plane_of(t), v);
      }
      return;
    }
#pragma omp parallel num_threads(reduced::worker_threads())
    {
      // Bands of at least 2·steps rows, so that the gaps of phase 2 never meet.
      const int bands = std::clamp(n / (2 * steps + 2), 1, omp_get_num_threads());
      const auto band_start = [&](int b) { return static_cast<int>(std::int64_t{n} * b / bands); };
#pragma omp for schedule(static)
      for (int b = 0; b < bands; ++b) {
        for (int s = 0; s < steps; ++s) {
          const int low = band_start(b) + (b > 0 ? s : 0);
          const int high = band_start(b + 1) - (b + 1 < bands ? s : 0);
          for (int v = low; v < high; ++v) sweep.row(plane_of(first + s), v);
        }
      }
#pragma omp for schedule(static)
      for (int b = 1; b < bands; ++b) {
        for (int s = 1; s < steps; ++s) {
          for (int v = band_start(b) - s; v < band_start(b) + s; ++v) {
            sweep.row(plane_of(first + s), v);
          }
        }
      }
    }
  }

  /// Step 3 for a signed field, planes [first, end): records the regions beyond the band.
  void scan_regions(int first, int end) {
    const std::int64_t n = m_last + 1;
#pragma omp parallel num_threads(reduced::worker_threads()) if (m_parallel)
    {
      std::vector<std::uint32_t> words(static_cast<std::size_t>(n * n));
#pragma omp for schedule(dynamic, 1)
      for (int k = first; k < end; ++k) {
        for (std::int64_t node = 0; node < n * n; ++node) {
          words[static_cast<std::size_t>(node)] = m_slots.load(k * n * n + node);
        }
        m_regions.scan_plane(k, words.data(), exact_bit, inside_bit);
      }
    }
  }
  /// Step 3: decides the side of each region beyond the band.
  void resolve_regions() { m_regions.resolve(); }

  /// Replaces the slot words of planes k in [first, end) by the distances to their triangles,
  /// negative inside for a signed field (after resolve_regions()).
  void finish_planes(int first, int end, std::vector<float>& values) const {
    const auto triangles = m_bvh.triangles();
    const GridGeometry& g = m_geometry;
#pragma omp parallel for num_threads(reduced::worker_threads()) schedule(static) if (m_parallel)
    for (int k = first; k < end; ++k) {
      for (int j = 0; j <= m_last; ++j) {
        const std::span<const detail::BandRegions::Run> runs =
            m_signed ? m_regions.runs(j, k) : std::span<const detail::BandRegions::Run>();
        std::size_t r = 0;
        for (int i = 0; i <= m_last; ++i) {
          const std::int64_t node = g.node_index(i, j, k);
          const std::uint32_t word = m_slots.load(node);
          assert((word & triangle_bits) != unknown_triangle);  // the sweeps reach every node
          const double distance =
              std::sqrt(triangles[word & triangle_bits].squared_distance(g.node_position(i, j, k)));
          bool inside = false;
          if (m_signed) {
            while (r < runs.size() && i >= runs[r].end) ++r;
            const bool in_region = r < runs.size() && i >= runs[r].begin;
            inside = in_region ? m_regions.inside(j, k, r) : (word & inside_bit) != 0;
          }
          values[static_cast<std::size_t>(node)] =
              static_cast<float>(inside ? -distance : distance);
        }
      }
    }
  }

 private:
  class Candidates;

  /// One cone sweep's geometry: the strides of its rows, the 3×3 neighbours behind a node, and
  /// for each of them the last earlier sweep that offered the same neighbour.
  class Sweep {
   public:
    /// Sweep `number` (1–6) runs along axis 2 − (number − 1)/2, upwards for odd numbers.
    Sweep(const FieldBuilder& builder, int number) noexcept
        : m_builder(builder),
          m_number(static_cast<std::uint32_t>(number)),
          m_axis(axis_of(number)),
          m_direction(direction_of(number)),
          m_u_axis(m_axis == 0 ? 1 : 0),
          m_v_axis(m_axis == 2 ? 1 : 2) {
      const std::int64_t n = builder.m_last + 1;
      const std::int64_t stride[3] = {1, n, n * n};
      m_su = stride[m_u_axis];
      for (int e = 0; e < 9; ++e) {
        int offset[3];
        offset[m_axis] = -m_direction;
        offset[m_u_axis] = e % 3 - 1;
        offset[m_v_axis] = e / 3 - 1;
        m_around[static_cast<std::size_t>(e)] =
            offset[0] * stride[0] + offset[1] * stride[1] + offset[2] * stride[2];
        // The neighbour is behind the node in every sweep whose axis component of the offset
        // is minus that sweep's direction.
        int previous = -1;
        for (int earlier = number - 1; earlier >= 1 && previous < 0; --earlier) {
          if (offset[axis_of(earlier)] == -direction_of(earlier)) previous = earlier;
        }
        m_offered_in[static_cast<std::size_t>(e)] = previous;
      }
    }

    int direction() const noexcept { return m_direction; }

    /// Updates row v of `plane` from the plane behind it.
    void row(int plane, int v) const noexcept {
      const FieldBuilder& b = m_builder;
      const GridGeometry& g = b.m_geometry;
      const int last = b.m_last;
      int c[3];
      c[m_axis] = plane;
      c[m_v_axis] = v;
      c[m_u_axis] = 0;
      const std::int64_t start = g.node_index(c[0], c[1], c[2]);
      const bool inner_row = v > 0 && v < last;
      for (int u = 0; u <= last; ++u) {
        const std::int64_t node = start + u * m_su;
        const std::uint32_t word = b.m_slots.load(node);
        if ((word & exact_bit) != 0) continue;
        c[m_u_axis] = u;
        Candidates candidates(word & ~changed_bits, g.node_position(c[0], c[1], c[2]),
                              b.m_prepared.data());
        const bool inner = inner_row && u > 0 && u < last;
        for (std::size_t e = 0; e < 9; ++e) {
          if (!inner) {
            const int du = static_cast<int>(e % 3) - 1, dv = static_cast<int>(e / 3) - 1;
            if (u + du < 0 || u + du > last || v + dv < 0 || v + dv > last) continue;
          }
          const std::uint32_t neighbour = b.m_slots.load(node + m_around[e]);
          if (static_cast<int>((neighbour & changed_bits) >> changed_shift) > m_offered_in[e]) {
            candidates.offer(neighbour);
          }
        }
        if (candidates.word() != (word & ~changed_bits)) {
          b.m_slots.store(node, candidates.word() | m_number << changed_shift);
        }
      }
    }

   private:
    static int axis_of(int number) noexcept { return 2 - (number - 1) / 2; }
    static int direction_of(int number) noexcept { return number % 2 == 1 ? 1 : -1; }

    const FieldBuilder& m_builder;
    std::uint32_t m_number;
    int m_axis, m_direction, m_u_axis, m_v_axis;
    std::int64_t m_su;
    std::array<std::int64_t, 9> m_around;
    /// Per neighbour: the last earlier sweep that offered it (−1: none). A neighbour whose
    /// triangle last changed no later than that (0: before the sweeps) was weighed then and is
    /// not offered again.
    std::array<int, 9> m_offered_in;
  };

  /// A node's best candidate during a sweep. Distances are computed only when two different
  /// triangles compete, each at most once per node.
  class Candidates {
   public:
    Candidates(std::uint32_t word, const Eigen::Vector3d& p,
               const detail::PreparedTriangle* triangles) noexcept
        : m_p(p), m_triangles(triangles), m_word(word) {}

    void offer(std::uint32_t neighbour) noexcept {
      const std::uint32_t candidate = neighbour & triangle_bits;
      const std::uint32_t own = m_word & triangle_bits;
      if (candidate == unknown_triangle || candidate == own) return;
      if (own == unknown_triangle) {
        m_word = candidate | (neighbour & inside_bit);  // step 3: the neighbour's side
        return;
      }
      for (int s = 0; s < m_seen; ++s) {
        if (m_rejected[s] == candidate) return;
      }
      if (m_distance < 0.0) m_distance = m_triangles[own].squared_distance(m_p);
      const double distance = m_triangles[candidate].squared_distance(m_p);
      m_rejected[m_seen++] = distance < m_distance ? own : candidate;
      if (distance < m_distance) {
        m_word = candidate | (m_word & inside_bit);
        m_distance = distance;
      }
    }
    std::uint32_t word() const noexcept { return m_word; }

   private:
    Eigen::Vector3d m_p;
    const detail::PreparedTriangle* m_triangles;
    std::uint32_t m_word;
    double m_distance = -1.0;  // squared distance to the own triangle; < 0 until needed
    std::uint32_t m_rejected[9];
    int m_seen = 0;
  };

  /// Finds node (i, j, k)'s closest triangle within squared distance `bound` and, if there is
  /// one, stores it as exact, with the side its pseudonormal gives.
  bool make_exact(int i, int j, int k, double bound, int hint, detail::BvhHit& hit) const {
    const Eigen::Vector3d p = m_geometry.node_position(i, j, k);
    if (!m_bvh.closest(p, bound, hint, hit)) return false;
    std::uint32_t word = static_cast<std::uint32_t>(hit.slot) | exact_bit;
    if (m_signed) {
      const auto& triangle = m_bvh.triangles()[static_cast<std::size_t>(hit.slot)];
      const Eigen::Vector3d& normal =
          m_normals[static_cast<std::size_t>(triangle.index)].of(hit.closest.region);
      if ((p - hit.closest.point).dot(normal) < 0.0) word |= inside_bit;
    }
    m_slots.store(m_geometry.node_index(i, j, k), word);
    return true;
  }

  GridGeometry m_geometry;
  int m_last;     // cells: the last node index per axis
  double m_band;  // metres
  bool m_signed;
  bool m_parallel;  // OpenMP for grids of at least min_parallel_plane nodes per plane
  detail::TriangleBvh m_bvh;
  std::vector<detail::TrianglePseudonormals> m_normals;  // mesh order; signed fields only
  std::vector<detail::PreparedTriangle> m_prepared;      // leaf order, like m_bvh.triangles()
  SlotWords m_slots;
  detail::BandRegions m_regions;  // signed fields only
};

DistanceGrid distance_field(const std::string& caller, const TriangleMesh& mesh,
                            const DistanceFieldOptions& options, bool is_signed) {
  reduced::validate(mesh);
  if (mesh.num_triangles() == 0) throw MeshError(caller + ": the mesh has no triangles");
  if (mesh.num_triangles() > max_triangles) {
    throw MeshError(caller + ": " + std::to_string(mesh.num_triangles()) +
                    " triangles exceed the limit of " + std::to_string(max_triangles));
  }
  const GridGeometry geometry = field_geometry(caller, mesh, options);
  const int n = geometry.nodes_per_axis();
  const int sweep_steps =
      std::clamp(n / (8 * reduced::worker_threads()), min_sweep_steps, max_sweep_steps);
  const int sweep_units = ceil_div(n - 1, sweep_steps);
  const int plane_units = ceil_div(n, planes_per_unit);
  // Whether a closest point can lie outside the box (then the faces' nodes are seeded).
  const bool seed_boundary = !geometry.box().contains(vertex_bounds(mesh));
  reduced::StageProgress progress(options.progress, stage_name,
                                  ceil_div(n, block_nodes) + (seed_boundary ? plane_units : 0) +
                                      6 * sweep_units + (is_signed ? plane_units + 1 : 0) +
                                      plane_units);

  std::vector<float> values(static_cast<std::size_t>(geometry.node_count()));
  FieldBuilder builder(mesh, geometry, options.exact_band, is_signed, values);
  std::int64_t exact = 0;
  for (int layer = 0; layer < builder.block_layers(); ++layer) {
    exact += builder.band_layer(layer);
    progress.advance();
  }
  if (seed_boundary) {
    for (int first = 0; first < n; first += planes_per_unit) {
      builder.seed_boundary(first, std::min(n, first + planes_per_unit));
      progress.advance();
    }
  } else if (exact == 0) {
    builder.seed_corners();
  }
  for (int sweep = 1; sweep <= 6; ++sweep) {
    for (int first = 1; first < n; first += sweep_steps) {
      builder.cone_sweep(sweep, first, std::min(n, first + sweep_steps));
      progress.advance();
    }
  }
  if (is_signed) {
    for (int first = 0; first < n; first += planes_per_unit) {
      builder.scan_regions(first, std::min(n, first + planes_per_unit));
      progress.advance();
    }
    builder.resolve_regions();
    progress.advance();
  }
  for (int first = 0; first < n; first += planes_per_unit) {
    builder.finish_planes(first, std::min(n, first + planes_per_unit), values);
    progress.advance();
  }
  progress.finish();
  return DistanceGrid(geometry, std::move(values), is_signed);
}

}  // namespace

DistanceGrid signed_distance_field(const TriangleMesh& closed_mesh,
                                   const DistanceFieldOptions& options) {
  return distance_field("signed_distance_field", closed_mesh, options, true);
}

DistanceGrid unsigned_distance_field(const TriangleMesh& mesh,
                                     const DistanceFieldOptions& options) {
  return distance_field("unsigned_distance_field", mesh, options, false);
}

}  // namespace khz::contact
