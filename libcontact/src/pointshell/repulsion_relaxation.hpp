#pragma once
// One level of multi-resolution particle repulsion (thesis §3.8.1): the new particles repel each
// other and the frozen particles of coarser levels while staying on a level set.

#include <khz/contact/common.hpp>
#include <khz/contact/field/distance_grid.hpp>

#include <khz/reduced/stage_progress.hpp>

#include <Eigen/Core>

#include <vector>

namespace khz::contact::detail {

/// Lengths in metres.
struct RelaxationSettings {
  double level = 0.0;    ///< The level set the particles stay on.
  double radius = 0.0;   ///< R, the kernel's radius.
  double spacing = 0.0;  ///< Expected point spacing √(A/N), the unit of `tolerance`.
  double step = 0.0;     ///< η: the move under unit force, at most (each particle adapts its own).
  double max_move = 0.0;  ///< Longest move of one particle in one iteration.
  /// Converged once the mean move < tolerance · spacing, with at most 1% of the projections
  /// failing.
  double tolerance = 0.0;
  int max_iterations = 0;
  double projection_tolerance = 0.0;  ///< ε.
  double projection_max_step = 0.0;   ///< Longest Newton step.
};

/// What relax_level() did; figures of its last iteration.
struct RelaxationResult {
  int iterations = 0;
  bool converged = false;
  double mean_step = 0.0;      ///< Mean η of the particles (m).
  double mean_movement = 0.0;  ///< Mean distance moved, after projection (m).
  double max_movement = 0.0;   ///< Largest distance moved (m).
  Eigen::Index failed_projections = 0;
};

/// Relaxes rows [frozen, count) of `points` while rows [0, frozen) stay fixed. `normals` holds
/// the unit field gradient at every row (the moving rows' are updated). Each iteration (Jacobi,
/// so the result does not depend on the thread count):
/// 1. every moving particle sums g(d/R) times the unit vector from each neighbour closer than
///    R, and keeps the part tangent to the level set;
/// 2. every moving particle moves by its own η times that force (at most max_move), and
///    Newton's method projects it back onto the level set; one whose projection fails stays
///    put.
/// A particle's η halves when its force reverses direction (it stepped over its equilibrium)
/// or its projection fails, and grows back by 1.2× per iteration otherwise, up to `step`: a
/// few particles oscillating at a kink of the level set do not slow the others down.
/// Neighbours come from Verlet lists built on a hash grid (radius 1.75 R) and rebuilt once some
/// particle has moved 0.375 R from where the lists were built.
/// `progress` advances by one per iteration.
/// @throws Cancelled (from `progress`).
RelaxationResult relax_level(const DistanceGrid& field, PointMatrix& points, Eigen::Index frozen,
                             Eigen::Index count, std::vector<Eigen::Vector3d>& normals,
                             const RelaxationSettings& settings, reduced::StageProgress& progress);

}  // namespace khz::contact::detail
