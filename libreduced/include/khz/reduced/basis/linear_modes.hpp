#pragma once
// Linear modal analysis: the lowest vibration modes K ψ = λ M ψ of the rest shape (thesis
// eq. 2.43, §2.8.3), for anchored and free-floating (§2.8.7) objects.

#include <khz/reduced/export.hpp>
#include <khz/reduced/fem/fem_model.hpp>
#include <khz/reduced/progress.hpp>

#include <Eigen/Core>

#include <span>
#include <vector>

namespace khz::reduced {

/// Options of compute_linear_modes().
struct LinearModesOptions {
  /// k: deformation modes wanted (≥ 1), not counting rigid modes.
  int num_modes = 20;
  /// Mass matrix of the eigenproblem and of the normalization ΨᵀMΨ = I.
  MassLumping mass = MassLumping::consistent;
  /// ARPACK's convergence criterion: relative residual of each Ritz value; 0 means machine
  /// precision (eigenvalues then agree with a dense solver to ~1e-12).
  double tolerance = 0.0;
  /// Implicit restarts of the Lanczos process before giving up (SolverError).
  int max_restarts = 300;
  /// Reports stage "linear modes": the factorization, then each application of the shift-
  /// inverted operator (the total is an estimate, raised if ARPACK needs more restarts).
  /// Cancel by returning false.
  ProgressCallback progress;
};

/// Result of compute_linear_modes(): mass-orthonormal eigenvectors on the full dofs.
struct KHZ_REDUCED_API LinearModes {
  /// λ₁ ≤ … ≤ λ_k of the deformation modes (rad²/s²): ψᵢ vibrates at √λᵢ/2π Hz.
  Eigen::VectorXd eigenvalues;
  /// Ψ, 3n × k, column i the mode of eigenvalue i; ΨᵀMΨ = I; rows of fixed vertices are zero.
  Eigen::MatrixXd modes;
  /// Eigenvalues of the rigid modes of an unconstrained object, |λ| ≈ round-off; empty when
  /// vertices are fixed.
  Eigen::VectorXd rigid_eigenvalues;
  /// 3n × 6c for an unconstrained mesh of c connected components: M-orthonormal, spanning the
  /// translations and infinitesimal rotations of each component, M-orthogonal to `modes`.
  Eigen::MatrixXd rigid_modes;
  /// The anchors the modes were computed for (sorted, distinct).
  std::vector<int> fixed_vertices;
  /// The mass matrix of the eigenproblem (LinearModesOptions::mass).
  MassLumping mass = MassLumping::consistent;
  /// Solves with the factorization of K − σM that the Lanczos process needed (its cost).
  int solves = 0;

  /// Vibration frequencies √λᵢ / 2π (Hz) of the deformation modes.
  Eigen::VectorXd frequencies_hz() const;
  /// True when no vertex is fixed (the rigid modes were separated out).
  bool unconstrained() const noexcept { return fixed_vertices.empty(); }
};

/// The k lowest generalized eigenpairs K(0) ψ = λ M ψ of the rest shape (eq. 2.43), by ARPACK's
/// implicitly restarted Lanczos method in shift-invert mode on a CHOLMOD factorization.
///
/// With fixed vertices the eigenproblem lives on the free dofs and the shift is 0 (one Cholesky
/// factorization of K). Without, K is singular: a small negative shift makes K − σM positive
/// definite, 6 modes per connected component are computed in addition, and they must come out
/// as rigid modes (eigenvalue below 1e-6·λ₁ relative to the first deformation mode, and
/// M-orthogonal to nothing but rigid motions); they are returned apart from the deformation
/// modes.
///
/// @param fixed_vertices anchors; they must remove every rigid motion of every connected
///                       component (e.g. 3 non-collinear vertices each), or none may be fixed.
/// @throws Error for invalid options or a vertex index out of range, or if k plus the rigid
///         modes reaches the number of free dofs; SolverError if the anchors leave K singular
///         (the message says so), if ARPACK does not converge within max_restarts, or if the
///         rigid modes of an unconstrained mesh cannot be separated; Cancelled.
KHZ_REDUCED_API LinearModes compute_linear_modes(const FemModel& model,
                                                 std::span<const int> fixed_vertices,
                                                 const LinearModesOptions& options = {});

}  // namespace khz::reduced
