#include "pointshell/repulsion_seeding.hpp"

#include <khz/contact/pointshell/pointshell_sampling.hpp>
#include <khz/reduced/worker_threads.hpp>

#include "pointshell/repulsion_hash_grid.hpp"
#include "pointshell/repulsion_projection.hpp"
#include "pointshell/split_mix.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

namespace khz::contact::detail {

namespace {

/// Random candidates per row of the level: enough that every hole the midpoints leave has some.
constexpr Eigen::Index candidates_per_row = 4;
/// Coarser points closer than this, in the coarser levels' spacing, are lattice neighbours whose
/// midpoint is a candidate. A relaxed level's nearest neighbours lie within 1.35 spacings and
/// the next ring beyond 1.7 (bench_pointshell), so 1.4 takes the first ring only: a triangular
/// lattice's vertices and edge midpoints form the lattice of half its spacing, with 4× its
/// points — the next level's count. Measured on dino.off (262k points in 5 levels): 1.3 left
/// more rows to random candidates and took 10% longer, 1.5 no faster.
constexpr double neighbour_reach = 1.4;
/// Dart-throwing distance of the midpoint candidates, in spacings: 0.8 kept 99% of the rows on
/// dino.off; 0.9 left more rows to random candidates and took 20% longer, 0.7 no faster.
constexpr double midpoint_radius = 0.8;
/// Dart-throwing distances of the random candidates, in spacings: the first pass, the last, and
/// the shrink per pass. Random sequential adsorption jams near 0.83 spacings; with four
/// candidates per row, 0.75 fills most rows and 0.6 nearly all.
constexpr double first_radius = 0.75;
constexpr double last_radius = 0.6;
constexpr double radius_shrink = 0.95;
// Below this many points a parallel loop costs more than it saves.
constexpr Eigen::Index parallel_threshold = 2048;

/// Candidate starting points, projected onto the level set where that converged.
struct Candidates {
  PointMatrix points;
  std::vector<Eigen::Vector3d> normals;  ///< The unit field gradient; zero where not on_level.
  std::vector<char> on_level;            ///< Whether the projection converged.

  Eigen::Index size() const noexcept { return points.rows(); }
};

/// Projects `samples` onto the level set, in parallel; a sample whose projection fails keeps its
/// position.
Candidates projected(const DistanceGrid& field, const SeedingTarget& target,
                     const PointMatrix& samples) {
  const Eigen::Index count = samples.rows();
  Candidates candidates{
      samples,
      std::vector<Eigen::Vector3d>(static_cast<std::size_t>(count), Eigen::Vector3d::Zero()),
      std::vector<char>(static_cast<std::size_t>(count), 0)};
#pragma omp parallel for num_threads(reduced::worker_threads()) \
    schedule(dynamic, 256) if (count > parallel_threshold)
  for (Eigen::Index k = 0; k < count; ++k) {
    const LevelSetProjection p =
        project_onto_level_set(field, target.level, samples.row(k).transpose(),
                               target.projection_tolerance, target.projection_max_step);
    const auto i = static_cast<std::size_t>(k);
    if (!p.converged) continue;
    candidates.on_level[i] = 1;
    candidates.points.row(k) = p.point.transpose();
    candidates.normals[i] = p.normal;
  }
  return candidates;
}

/// The midpoints of the pairs of rows [0, count) of `points` closer than `reach`: at most
/// `limit` of them, in scanline order of cells; serial, so reproducible.
PointMatrix neighbour_midpoints(const PointMatrix& points, Eigen::Index count, double reach,
                                Eigen::Index limit) {
  const RepulsionHashGrid grid(points, count, reach);
  std::vector<Eigen::Vector3d> midpoints;
  const auto full = [&] { return static_cast<Eigen::Index>(midpoints.size()) == limit; };
  for (std::size_t cell = 0; cell < grid.cell_count() && !full(); ++cell) {
    const RepulsionHashGrid::Range own = grid.cell_slots(cell);
    const RepulsionHashGrid::Neighbourhood around = grid.neighbourhood(cell);
    for (std::int32_t a = own.begin; a < own.end; ++a) {
      for (int c = 0; c < around.count; ++c) {
        const RepulsionHashGrid::Range range = around.ranges[static_cast<std::size_t>(c)];
        for (std::int32_t b = range.begin; b < range.end && !full(); ++b) {
          if (grid.slot_point(b) > grid.slot_point(a) &&
              (grid.slot_position(b) - grid.slot_position(a)).squaredNorm() < reach * reach) {
            midpoints.push_back(0.5 * (grid.slot_position(a) + grid.slot_position(b)));
          }
        }
      }
    }
  }
  PointMatrix result(static_cast<Eigen::Index>(midpoints.size()), 3);
  for (std::size_t k = 0; k < midpoints.size(); ++k) {
    result.row(static_cast<Eigen::Index>(k)) = midpoints[k].transpose();
  }
  return result;
}

/// Rows [0, next) of `points` are placed. Dart throwing keeps projected candidates, visited in
/// scanline order of grid cells and by index within a cell, each no closer than r spacings to
/// the placed rows and to those kept before it, for r from `first` down to `last` shrinking
/// by 5% per pass; they fill rows from `next` on, up to `end`. Marks the kept candidates in
/// `taken` and returns the first row still empty.
Eigen::Index throw_darts(const Candidates& candidates, double first, double last, double spacing,
                         Eigen::Index next, Eigen::Index end, PointMatrix& points,
                         std::vector<Eigen::Vector3d>& normals, std::vector<char>& taken) {
  const Eigen::Index placed = next;
  // A candidate that a placed row blocks at the last radius is never kept: leave it out of the
  // dart throwing (the same result, found in parallel). Most are: a level's random candidates
  // outnumber the rows that midpoints leave empty 400 to 1 on dino.off.
  std::vector<char> open(static_cast<std::size_t>(candidates.size()), 0);
  {
    // Cells of a spacing: a candidate's own cell holds a blocking row more often than with
    // cells of the last radius, and the whole search took 20% less time (dino.off).
    const RepulsionHashGrid placed_grid(points, placed, spacing);
#pragma omp parallel for num_threads(reduced::worker_threads()) \
    schedule(dynamic, 1024) if (candidates.size() > parallel_threshold)
    for (Eigen::Index k = 0; k < candidates.size(); ++k) {
      const auto i = static_cast<std::size_t>(k);
      open[i] = candidates.on_level[i] != 0 && taken[i] == 0 &&
                !placed_grid.has_point_within(candidates.points.row(k).transpose(), last * spacing);
    }
  }
  std::vector<Eigen::Index> open_rows;  // candidate numbers, ascending
  for (Eigen::Index k = 0; k < candidates.size(); ++k) {
    if (open[static_cast<std::size_t>(k)] != 0) open_rows.push_back(k);
  }
  const auto count = static_cast<Eigen::Index>(open_rows.size());
  PointMatrix all(placed + count, 3);
  all.topRows(placed) = points.topRows(placed);
  for (Eigen::Index o = 0; o < count; ++o) {
    all.row(placed + o) = candidates.points.row(open_rows[static_cast<std::size_t>(o)]);
  }
  const RepulsionHashGrid grid(all, all.rows(), first * spacing);
  // By slot, so that a neighbourhood's flags are contiguous.
  std::vector<char> kept(static_cast<std::size_t>(all.rows()), 0);
  for (std::size_t slot = 0; slot < kept.size(); ++slot) {
    kept[slot] = grid.slot_point(static_cast<std::int32_t>(slot)) < placed ? 1 : 0;
  }
  // Per candidate, the distance of a kept point found within the last pass's radius: kept points
  // stay, so a later pass with a smaller radius needs to look again only if it is farther.
  std::vector<double> blocked(static_cast<std::size_t>(count),
                              std::numeric_limits<double>::infinity());
  for (double r = first; r >= last && next < end; r *= radius_shrink) {
    const double radius = r * spacing;
    for (std::size_t cell = 0; cell < grid.cell_count() && next < end; ++cell) {
      const RepulsionHashGrid::Range own = grid.cell_slots(cell);
      RepulsionHashGrid::Neighbourhood around;  // found once a candidate of the cell needs it
      for (std::int32_t slot = own.begin; slot < own.end && next < end; ++slot) {
        const Eigen::Index o = grid.slot_point(slot) - placed;
        if (o < 0) continue;
        const auto i = static_cast<std::size_t>(o);
        const Eigen::Index k = open_rows[i];
        if (taken[static_cast<std::size_t>(k)] != 0 || blocked[i] < radius) continue;
        if (around.count == 0) around = grid.neighbourhood(cell);
        const Eigen::Vector3d& p = grid.slot_position(slot);
        for (int c = 0; c < around.count && blocked[i] >= radius; ++c) {
          const RepulsionHashGrid::Range range = around.ranges[static_cast<std::size_t>(c)];
          for (std::int32_t other = range.begin; other < range.end; ++other) {
            if (kept[static_cast<std::size_t>(other)] == 0) continue;
            const double d = (grid.slot_position(other) - p).norm();
            if (d < radius) {
              blocked[i] = d;
              break;
            }
          }
        }
        if (blocked[i] < radius) continue;
        kept[static_cast<std::size_t>(slot)] = 1;
        taken[static_cast<std::size_t>(k)] = 1;
        points.row(next) = candidates.points.row(k);
        normals[static_cast<std::size_t>(next)] = candidates.normals[static_cast<std::size_t>(k)];
        ++next;
      }
    }
  }
  return next;
}

/// Interleaves the low 21 bits of x with two zero bits after each (Morton order).
std::uint64_t spread(std::uint64_t x) noexcept {
  x &= 0x1fffff;
  x = (x | x << 32) & 0x1f00000000ffffULL;
  x = (x | x << 16) & 0x1f0000ff0000ffULL;
  x = (x | x << 8) & 0x100f00f00f00f00fULL;
  x = (x | x << 4) & 0x10c30c30c30c30c3ULL;
  x = (x | x << 2) & 0x1249249249249249ULL;
  return x;
}

/// Reorders rows [begin, end) along a Morton curve over the field's grid cells, so that
/// particles near in space are near in memory and the repulsion's neighbour loads mostly hit
/// the cache: iterations 1.6× faster at 256k points (dino.off, one core). Reproducible: the
/// keys are unique per row.
void sort_spatially(const DistanceGrid& field, Eigen::Index begin, Eigen::Index end,
                    PointMatrix& points, std::vector<Eigen::Vector3d>& normals) {
  const GridGeometry& grid = field.geometry();
  std::vector<std::pair<std::uint64_t, Eigen::Index>> keyed;
  keyed.reserve(static_cast<std::size_t>(end - begin));
  for (Eigen::Index s = begin; s < end; ++s) {
    const Eigen::Vector3d cell = (points.row(s).transpose() - grid.origin) / grid.spacing;
    std::uint64_t key = 0;
    for (int axis = 0; axis < 3; ++axis) {
      const double clamped = std::clamp(cell[axis], 0.0, static_cast<double>(grid.cells));
      key |= spread(static_cast<std::uint64_t>(clamped)) << axis;
    }
    keyed.emplace_back(key, s);
  }
  std::sort(keyed.begin(), keyed.end());
  const PointMatrix old_points = points.middleRows(begin, end - begin);
  const std::vector<Eigen::Vector3d> old_normals(normals.begin() + begin, normals.begin() + end);
  for (std::size_t k = 0; k < keyed.size(); ++k) {
    const Eigen::Index from = keyed[k].second - begin;
    points.row(begin + static_cast<Eigen::Index>(k)) = old_points.row(from);
    normals[static_cast<std::size_t>(begin) + k] = old_normals[static_cast<std::size_t>(from)];
  }
}

}  // namespace

void seed_level(const DistanceGrid& field, const TriangleMesh& level_set,
                const SeedingTarget& target, std::uint64_t seed, Eigen::Index begin,
                Eigen::Index end, PointMatrix& points, std::vector<Eigen::Vector3d>& normals) {
  const Eigen::Index rows = end - begin;
  Eigen::Index next = begin;
  if (begin > 1) {
    // The coarser levels' lattice, subdivided: the midpoints of neighbouring coarser points.
    const double coarser_spacing =
        target.spacing * std::sqrt(static_cast<double>(end) / static_cast<double>(begin));
    const Candidates candidates =
        projected(field, target,
                  neighbour_midpoints(points, begin, neighbour_reach * coarser_spacing,
                                      candidates_per_row * rows));
    std::vector<char> taken(static_cast<std::size_t>(candidates.size()), 0);
    next = throw_darts(candidates, midpoint_radius, midpoint_radius, target.spacing, next, end,
                       points, normals, taken);
  }

  // The rows left: a Poisson-disk choice among random points, then any projected candidate, then
  // (off the level set) the others.
  const Eigen::Index count = candidates_per_row * rows;
  const Pointshell samples = random_pointshell(level_set, count, split_mix(seed));
  const Candidates candidates = projected(field, target, samples.points);
  std::vector<char> taken(static_cast<std::size_t>(count), 0);
  next = throw_darts(candidates, first_radius, last_radius, target.spacing, next, end, points,
                     normals, taken);
  for (const char wanted : {char{1}, char{0}}) {
    for (Eigen::Index k = 0; k < count && next < end; ++k) {
      const auto i = static_cast<std::size_t>(k);
      if (taken[i] != 0 || candidates.on_level[i] != wanted) continue;
      taken[i] = 1;
      points.row(next) = candidates.points.row(k);
      normals[static_cast<std::size_t>(next)] =
          wanted != 0 ? candidates.normals[i]
                      : Eigen::Vector3d(-samples.normals.row(k).transpose());
      ++next;
    }
  }
  sort_spatially(field, begin, end, points, normals);
}

}  // namespace khz::contact::detail
