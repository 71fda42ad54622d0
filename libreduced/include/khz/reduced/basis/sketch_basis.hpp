#pragma once
// The basis from sketched force loads (thesis §2.8.2): recorded loads → greedy thinning by
// force distance → full nonlinear static solves → thinning by mass distance → mass-PCA.

#include <khz/reduced/basis/basis.hpp>
#include <khz/reduced/basis/force_load.hpp>
#include <khz/reduced/basis/mass_pca.hpp>
#include <khz/reduced/export.hpp>
#include <khz/reduced/fem/fem_model.hpp>
#include <khz/reduced/progress.hpp>
#include <khz/reduced/solvers/static_solver.hpp>

#include <Eigen/Core>

#include <span>
#include <string>
#include <vector>

namespace khz::reduced {

/// Options of sketch_basis().
struct KHZ_REDUCED_API SketchBasisOptions {
  /// δ_f ≥ 0 (N): the loads sent to the static solver are pairwise at least this far apart in
  /// the Euclidean norm of their full force vectors, ‖f_a − f_b‖. 0 solves every load. A tip
  /// load of total force F spread evenly over m vertices has norm F/√m.
  double force_separation = 0.0;
  /// h_f ≥ 0 (N): width of the density kernel for the loads; 0 means h_f = δ_f.
  double force_kernel_width = 0.0;
  /// δ_u ≥ 0 (m·√kg): the static deformations given to PCA are pairwise at least this far
  /// apart in the mass norm ‖u − v‖_M (thesis eq. 2.40). 0 keeps every deformation. For scale:
  /// a rigid translation by d of a body of mass m has mass norm d·√m.
  double deformation_separation = 0.0;
  /// h_u ≥ 0 (m·√kg): width of the density kernel for the deformations; 0 means h_u = δ_u.
  double deformation_kernel_width = 0.0;
  /// Load steps, iterations and tolerance of each full static solve.
  StaticSolveOptions static_solve;
  /// r: basis vectors (≥ 1, at most the number of deformations kept).
  int basis_size = 0;
  /// PCA metric. The deformation thinning measures with the lumped mass matrix for
  /// lumped_mass and with the consistent one otherwise.
  PcaMetric metric = PcaMetric::mass;
  /// In [0, 1), passed to principal_components(): directions whose singular value is below
  /// this fraction of σ₁ are absent.
  double rank_tolerance = 1e-10;
  /// When false (the default) a static solve that fails stops everything with SolverError
  /// naming the load. When true the load is skipped and listed in SketchReport::failures.
  bool skip_failed_solves = false;
  /// Receives the stages "force selection", "static solves" (one unit per solve, re-reported
  /// after every Newton iteration), "mass distances", "deformation selection" and "mass PCA".
  /// Cancel by returning false: it takes effect within one Newton iteration.
  /// static_solve.progress is ignored.
  ProgressCallback progress;

  /// @throws Error naming the first invalid value.
  void validate() const;
};

/// A load whose static solve failed and was skipped (SketchBasisOptions::skip_failed_solves).
struct SketchSolveFailure {
  int load = 0;         ///< Index in the loads given to sketch_basis().
  std::string message;  ///< The solver's SolverError::what().
};

/// What sketch_basis() did, for display and for refining a sketch later.
struct SketchReport {
  int num_loads = 0;  ///< Loads given.
  /// Loads that survived the force thinning and went to the static solver (increasing indices
  /// into the given loads).
  std::vector<int> selected_loads;
  /// Newton iterations of each selected load's static solve (same order as selected_loads),
  /// −1 for a failed one.
  std::vector<int> static_iterations;
  /// Skipped failed solves, in load order (empty unless skip_failed_solves).
  std::vector<SketchSolveFailure> failures;
  /// Loads whose deformation survived the mass-distance thinning, increasing: the columns of
  /// `deformations`.
  std::vector<int> kept_loads;
  /// The kept static deformations (m), 3n × kept_loads.size(); zero at the fixed vertices.
  /// Append new ones to refine a basis without solving these again.
  Eigen::MatrixXd deformations;
  /// Singular values of the kept deformations in the PCA metric (see PcaResult).
  Eigen::VectorXd singular_values;
};

/// The sketch basis (thesis §2.8.2). In order:
///  1. the loads are thinned to force separation δ_f, densest first (select_separated_samples
///     on force_distances);
///  2. each retained load f is solved to static equilibrium R(u) = f on the full model
///     (solve_static with `static_solve`, fixed vertices held);
///  3. the deformations are thinned to mass separation δ_u (mass_distances);
///  4. mass-PCA (principal_components) reduces them to r mass-orthonormal vectors.
/// The basis is zero at the fixed vertices (set exactly) and satisfies UᵀMU = I to round-off;
/// its recipe reads "sketch: N loads, M selected, S deformations kept, mass PCA to r=…".
///
/// @param fixed_vertices anchors (repeats allowed); they must remove the rigid motions, since
///                       each static solve needs a nonsingular stiffness matrix.
/// @param loads          recorded loads (≥ 1); forces on fixed vertices have no effect.
/// @throws Error for invalid options, no loads, a load or fixed vertex outside the mesh (naming
///         the load), or basis_size above the number of deformations kept or their numerical
///         rank; SolverError naming the load whose static solve failed (unless
///         skip_failed_solves; then only if every solve failed), or if the mass matrix is not
///         positive definite; Cancelled. Nothing is returned or reported on failure.
KHZ_REDUCED_API Basis sketch_basis(const FemModel& model, std::span<const int> fixed_vertices,
                                   std::span<const ForceLoad> loads,
                                   const SketchBasisOptions& options);

/// sketch_basis() that also describes what it did: `report` is assigned when the call
/// returns and left untouched when it throws.
KHZ_REDUCED_API Basis sketch_basis(const FemModel& model, std::span<const int> fixed_vertices,
                                   std::span<const ForceLoad> loads,
                                   const SketchBasisOptions& options, SketchReport& report);

}  // namespace khz::reduced
