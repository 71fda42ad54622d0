#pragma once
// Principal component analysis of deformations in the mass metric (thesis §2.8.1): the
// r-dimensional subspace that best represents a set of deformations, each vertex weighted by
// the mass it carries rather than by how densely the mesh is sampled there.

#include <khz/reduced/export.hpp>
#include <khz/reduced/fem/fem_model.hpp>
#include <khz/reduced/progress.hpp>

#include <Eigen/Core>

namespace khz::reduced {

/// Inner product under which principal_components() measures and orthonormalizes.
enum class PcaMetric {
  /// ⟨x, y⟩ = yᵀMx with the given (consistent) mass matrix, through a sparse Cholesky
  /// factorization M = PᵀLLᵀP with a fill-reducing ordering P (eq. 2.39–2.40).
  mass,
  /// The same with the row-sum lumped (diagonal) version of the given mass matrix.
  lumped_mass,
  /// Plain PCA, ⟨x, y⟩ = yᵀx; the mass matrix is not used. For comparison: it favours
  /// finely meshed regions.
  euclidean,
};

/// Options of principal_components().
struct PcaOptions {
  /// r: basis vectors wanted (≥ 1, at most the number of samples).
  int basis_size = 0;
  PcaMetric metric = PcaMetric::mass;
  /// Directions whose singular value is below rank_tolerance·σ₁ count as absent: asking for
  /// more basis vectors than the data has such directions is an error.
  double rank_tolerance = 1e-10;
  /// Reports stage "mass PCA". Cancel by returning false.
  ProgressCallback progress;
};

/// Result of principal_components().
struct PcaResult {
  /// U, 3n × r: the r principal directions in decreasing order of importance, orthonormal in
  /// the chosen metric (UᵀMU = I, or UᵀU = I for euclidean). Each column's sign is chosen so
  /// that its largest-magnitude entry is positive.
  Eigen::MatrixXd basis;
  /// All singular values σ₁ ≥ σ₂ ≥ … of the samples in the metric (min(3n, N) of them);
  /// the best rank-r approximation leaves Σ_{i>r} σᵢ² of squared error, so they guide r.
  Eigen::VectorXd singular_values;
};

/// The basis U minimizing Σᵢ ‖uᵢ − UUᵀM uᵢ‖²_M over the samples (hyperplane through the origin,
/// so zero deformation stays representable): z = LᵀPu turns this into Euclidean PCA, solved
/// by a thin QR and an SVD of the N-column sample matrix, and U = PᵀL⁻ᵀV maps back.
///
/// @param samples 3n × N deformations u₁ … u_N (columns, metres or any common scale).
/// @param mass    3n × 3n symmetric positive definite mass matrix (ignored for euclidean).
/// @throws Error on size mismatch, non-finite samples, basis_size outside [1, N] or above the
///         numerical rank; SolverError if the mass matrix is not positive definite; Cancelled.
KHZ_REDUCED_API PcaResult principal_components(const Eigen::MatrixXd& samples,
                                               const SparseMatrix& mass, const PcaOptions& options);

}  // namespace khz::reduced
