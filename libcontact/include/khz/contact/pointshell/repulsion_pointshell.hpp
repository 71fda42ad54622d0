#pragma once
// Multi-resolution pointshells by particle repulsion on a level set of a distance field
// (thesis §3.8.1): nested levels of quasi-uniform points, each four times as many as the one
// before, with inward normals, ready for the nested point tree (§3.9).

#include <khz/contact/common.hpp>
#include <khz/contact/export.hpp>
#include <khz/contact/field/distance_grid.hpp>
#include <khz/contact/field/mesh_distance_field.hpp>
#include <khz/contact/pointshell/pointshell.hpp>

#include <Eigen/Core>

#include <cstdint>
#include <vector>

namespace khz::contact {

/// Options of repulsion_pointshell(). Every length the method uses follows from the level set's
/// area A, the point count and the grid spacing h, so the defaults suit any model size; the
/// thesis tuned R and η by hand per scene (§3.8.1).
struct KHZ_CONTACT_API RepulsionOptions {
  /// n₀: points of level 0, ≥ 1. Level i has n₀·4ⁱ points (§3.8.1), so L levels hold
  /// n₀(4ᴸ − 1)/3 in all; those of the coarser levels plus four candidates per point of the
  /// finest (its seeding) at most 2³¹ − 1.
  Eigen::Index first_level_points = 64;
  /// L, ≥ 1.
  int levels = 4;
  /// Selects the random starting positions: the same seed gives the same pointshell, bit for
  /// bit, on any thread count.
  std::uint64_t seed = 0;
  /// Repulsion iterations allowed per level, ≥ 1. A level that has not converged by then keeps
  /// its current positions and is reported with converged = false (not an error).
  int max_iterations = 1000;
  /// Convergence, in (0, 1): a level stops once its points moved on average less than
  /// `tolerance` spacings in one iteration (spacing √(A/Nᵢ), Nᵢ the points of levels 0…i).
  /// Measured on dino.off, 262k points in 5 levels (bench_pointshell): 10⁻³ takes 115, 126,
  /// 96, 55 and 30 iterations on levels 0–4, for a nearest-neighbour spread (99th over 1st
  /// percentile) of 1.24 on the finest level; 2·10⁻³ about half as many, 1.29, in about 65% of
  /// the time; 4·10⁻³ a quarter, 1.35, in about 60%. (Before finer levels started from the
  /// coarser levels' midpoints, 10⁻³ took about 145 iterations per level for 1.27.)
  double tolerance = 1e-3;
  /// κ: the repulsion radius of level i is R = κ·√(A/Nᵢ) (the thesis halves R per level, which
  /// this approaches as Nᵢ₊₁/Nᵢ → 4). The default, 1.5, reaches the first ring of neighbours
  /// of a hexagonal packing (at 1.07 √(A/N)) but not the second: measured, a larger κ spreads
  /// points more evenly on smooth surfaces (κ = 2: 99th/1st nearest-neighbour percentile 1.22
  /// against 1.30 on a sphere) but pushes them together at features thinner than the spacing
  /// — the thesis's "points accumulate at sharp edges" (κ = 2 on dino.off: smallest distance
  /// 0.02–0.22 of the mean, against 0.23–0.52 at 1.5, over three seeds). In [1, 4].
  double radius_factor = 1.5;
  /// ε (m): the largest |d(p) − level| accepted when projecting a point onto the level set. 0
  /// picks 10⁻⁴ h.
  double projection_tolerance = 0.0;
  /// Reports the stages "pointshell level set" (1 unit), "particle repulsion level i" for each
  /// level (units: its seeding, its iterations and its nearest-neighbour statistics, total
  /// max_iterations + 2; finished early on convergence) and "pointshell normals" (units:
  /// points). Returning false cancels (Cancelled) within one iteration, or after the seeding.
  ProgressCallback progress;

  /// @throws Error naming the first invalid option.
  void validate() const;
};

/// What happened on one level of repulsion_pointshell(). Lengths in metres.
struct RepulsionLevelReport {
  Eigen::Index points = 0;    ///< Points added on this level (n₀·4ⁱ).
  double radius = 0.0;        ///< R, the repulsion kernel's radius.
  double spacing = 0.0;       ///< √(A/Nᵢ): the expected spacing of the points of levels 0…i.
  double initial_step = 0.0;  ///< η at the start: the move of a point under unit force.
  /// Mean η at the end: each point halves its own η whenever its force reverses or its
  /// projection fails.
  double final_step = 0.0;
  int iterations = 0;          ///< Repulsion iterations run.
  bool converged = false;      ///< Whether `tolerance` was met within max_iterations.
  double mean_movement = 0.0;  ///< Mean distance this level's points moved in the last iteration.
  double max_movement = 0.0;   ///< Largest distance moved in the last iteration.
  /// Points whose move could not be projected back onto the level set in the last iteration
  /// (they stayed where they were, on it).
  Eigen::Index failed_projections = 0;
  /// Distance from each point of levels 0…i to its nearest other point: smallest, largest,
  /// mean, largest/smallest, and the 1st and 99th percentiles — how uniformly levels 0…i
  /// sample the level set. On features thinner than the spacing a few points can come much
  /// closer than the rest (see RepulsionOptions::radius_factor); the percentiles ignore them.
  double nearest_min = 0.0;
  double nearest_max = 0.0;
  double nearest_mean = 0.0;
  double nearest_ratio = 0.0;
  double nearest_percentile_1 = 0.0;
  double nearest_percentile_99 = 0.0;
};

/// What repulsion_pointshell() did, for judging its result.
struct RepulsionReport {
  double level_set_area = 0.0;           ///< A (m²): area of the triangulated level set S.
  Eigen::Index level_set_triangles = 0;  ///< Triangles of S.
  double projection_tolerance = 0.0;     ///< ε used (m).
  std::vector<RepulsionLevelReport> levels;
  /// Points with |d(p) − level| > ε at the end: normally none; a level starts from points of
  /// S that could not be projected onto T only when too few others could, and those stay on S.
  std::vector<Eigen::Index> off_level_set;

  /// Whether every level converged.
  bool converged() const noexcept {
    for (const RepulsionLevelReport& level : levels) {
      if (!level.converged) return false;
    }
    return !levels.empty();
  }
};

/// A nested multi-resolution pointshell fitted by particle repulsion onto the level set
/// T = {d = level} of `field` (thesis §3.8.1): level 0 of a closed mesh's signed field, or
/// level 0 of PolygonSoupField::field for a polygon soup or thin structure (its offset surface
/// σ; an unsigned field at level σ works too, but keeps inner walls).
///
/// Level by level, n₀·4ⁱ new particles start as a Poisson-disk sample (dart throwing, at
/// least 0.6–0.8 spacings from each other and from the coarser levels' points): first among the
/// midpoints of neighbouring coarser points — a relaxed triangular lattice's edge midpoints and
/// vertices form the lattice of half its spacing, so the finest level of dino.off converges in
/// 30 iterations instead of 146 — then, for the rows left, among 4·n₀·4ⁱ area-weighted random
/// points of the marching-tetrahedra triangulation S of T (isosurface()), all projected onto T.
/// Then, with the points of coarser levels frozen, they repel each other and the frozen points
/// with the
/// thesis's finite-radius kernel, of force g(d/R) = 2(d/R)³ − 3(d/R)² + 1 for d < R and 0
/// beyond. Each iteration computes every force first and then moves every particle (Jacobi):
/// by its η times the force's part tangent to T, then back onto T by Newton's method along the
/// field's gradient (bisection where Newton stalls). Neighbours come from a spatial hash grid.
/// The points of levels 0…i together sample T about uniformly, at a spacing halving per level.
///
/// Normals are inward: minus the angle-weighted pseudonormal of the feature of
/// `surface_for_normals` closest to each point (inward_normals()). Pass the original closed
/// mesh (best at sharp edges), PolygonSoupField::offset_surface, or isosurface(field, level).
///
/// Non-convergence is reported, not thrown (RepulsionReport: per-level `converged`, points off
/// the level set); the caller decides. In parallel (OpenMP); the result does not depend on the
/// thread count. Cost: about 0.2 µs per point and iteration on two cores; 256k points in five
/// levels on dino.off's 256³ field take 2.8–3.4 s on two cores, 5.2 s on one (bench_pointshell).
///
/// @param field The distance field (m), signed or unsigned.
/// @param level The level (m) whose set T the points lie on, finite.
/// @param surface_for_normals The mesh whose pseudonormals give the (inward) point normals.
/// @param report If not null, receives what happened (replacing its content).
/// @throws Error for invalid options, a non-finite level, or a level set that does not cross
///         the grid; MeshError for an invalid `surface_for_normals` or one without triangles;
///         Cancelled.
KHZ_CONTACT_API Pointshell repulsion_pointshell(const DistanceGrid& field, double level,
                                                const TriangleMesh& surface_for_normals,
                                                const RepulsionOptions& options = {},
                                                RepulsionReport* report = nullptr);

/// repulsion_pointshell() on the zero level set of the signed distance field of a closed,
/// consistently oriented manifold mesh (signed_distance_field() with `field_options`, whose
/// progress callback, if empty, becomes options.progress), with normals from the mesh itself.
/// @throws as signed_distance_field() and repulsion_pointshell().
KHZ_CONTACT_API Pointshell repulsion_pointshell(const TriangleMesh& closed_mesh,
                                                const DistanceFieldOptions& field_options,
                                                const RepulsionOptions& options = {},
                                                RepulsionReport* report = nullptr);

}  // namespace khz::contact
