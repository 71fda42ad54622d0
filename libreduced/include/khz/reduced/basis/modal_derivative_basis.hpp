#pragma once
// The automatic basis of linear modes and their modal derivatives, weighted and reduced by
// mass-PCA (thesis §2.8.3, eq. 2.52; unconstrained objects §2.8.7).

#include <khz/reduced/basis/basis.hpp>
#include <khz/reduced/basis/linear_modes.hpp>
#include <khz/reduced/basis/mass_pca.hpp>
#include <khz/reduced/basis/modal_derivatives.hpp>
#include <khz/reduced/export.hpp>
#include <khz/reduced/fem/fem_model.hpp>
#include <khz/reduced/progress.hpp>

#include <Eigen/Core>

#include <span>

namespace khz::reduced {

/// The samples of eq. 2.52 (3n × (k + derivatives)): the modes scaled by λ₁/λⱼ, then the
/// derivatives mass-normalized and scaled by λ₁²/(λᵢλⱼ). Scaling favours the dominant
/// low-frequency modes and their derivatives, which high-frequency ones would otherwise mask.
/// @param mass the mass matrix the modes are normalized with.
/// @throws Error if the sizes disagree or a derivative is zero.
KHZ_REDUCED_API Eigen::MatrixXd weighted_modal_samples(const LinearModes& modes,
                                                       const ModalDerivatives& derivatives,
                                                       const SparseMatrix& mass);

/// Options of modal_derivative_basis().
struct ModalDerivativeBasisOptions {
  /// r: basis size (≥ 1, at most k + the number of derivatives). The thesis finds r ≈ 3k
  /// captures most of the derivative space (§2.13.2).
  int basis_size = 30;
  /// PCA metric; mass (consistent) unless comparing.
  PcaMetric metric = PcaMetric::mass;
  /// k and the eigensolver settings. Its progress callback is ignored: set `progress` below.
  LinearModesOptions modes;
  /// Derivative solver settings. Its progress callback is ignored: set `progress` below.
  ModalDerivativesOptions derivatives;
  /// Receives every stage: "linear modes", "Hessian contractions", "modal derivatives",
  /// "mass PCA". Cancel by returning false.
  ProgressCallback progress;
};

/// Linear modes → modal derivatives → eq. 2.52 weighting → mass-PCA to r vectors, in one call.
/// The result is mass-orthonormal and exactly zero at the fixed vertices. For an unconstrained
/// object it is also M-orthogonal to the rigid modes (§2.8.7): the samples are projected off
/// them before the PCA, since eq. 2.60's off-diagonal derivatives contain infinitesimal
/// rotations, which belong to the rigid frame a later coupling adds.
/// @throws as compute_linear_modes, compute_modal_derivatives and principal_components.
KHZ_REDUCED_API Basis modal_derivative_basis(const FemModel& model,
                                             std::span<const int> fixed_vertices,
                                             const ModalDerivativeBasisOptions& options = {});

}  // namespace khz::reduced
