#pragma once
// The a-posteriori basis: mass-PCA of the displacements of a full simulation (thesis §2.8,
// the statistical approach of [KLM01]; "re-simulation" in §2.13.1). Close to optimal for
// re-running that simulation with small changes, but only available after the expensive run.

#include <khz/reduced/basis/basis.hpp>
#include <khz/reduced/basis/mass_pca.hpp>
#include <khz/reduced/export.hpp>
#include <khz/reduced/fem/fem_model.hpp>
#include <khz/reduced/progress.hpp>

#include <Eigen/Core>

#include <span>

namespace khz::reduced {

/// Options of simulation_data_basis().
struct SimulationDataBasisOptions {
  /// PCA metric; mass (consistent) unless comparing.
  PcaMetric metric = PcaMetric::mass;
  /// Passed to principal_components(): directions below this fraction of σ₁ are absent.
  double rank_tolerance = 1e-10;
  /// A snapshot may move a fixed vertex by at most this fraction of the largest displacement
  /// entry of all snapshots (per component). FullNewmark holds them at exactly 0.
  double fixed_tolerance = 1e-12;
  /// Reports stage "mass PCA". Cancel by returning false.
  ProgressCallback progress;
};

/// Mass-PCA (thesis §2.8.1) of displacement snapshots of a full simulation, e.g. the
/// FullNewmark::displacement() after each step: the r-dimensional subspace through the origin
/// that best represents them in the mass metric. The result is mass-orthonormal, zero at the
/// fixed vertices (set exactly) and has recipe "simulation data: N snapshots, mass PCA to r=…".
///
/// @param fixed_vertices the anchors of the simulation (repeats allowed).
/// @param snapshots      3n × N displacements (m), one column per snapshot, N ≥ 1.
/// @param basis_size     r, in [1, N] and at most the numerical rank of the snapshots.
/// @throws Error if the snapshots do not have 3n rows or no column, an entry is not finite
///         (naming snapshot and vertex), a snapshot moves a fixed vertex (naming both), a fixed
///         vertex lies outside the mesh, the options are invalid, or basis_size is out of range
///         or above the rank; SolverError if the mass matrix is not positive definite; Cancelled.
KHZ_REDUCED_API Basis simulation_data_basis(const FemModel& model,
                                            std::span<const int> fixed_vertices,
                                            const Eigen::MatrixXd& snapshots, int basis_size,
                                            const SimulationDataBasisOptions& options = {});

}  // namespace khz::reduced
