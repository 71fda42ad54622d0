// The modal-derivative basis: eq. 2.52 weighting and mass-PCA (thesis §2.8.3, §2.8.7).
#include "generator_support.hpp"

#include <khz/reduced/basis/modal_derivative_basis.hpp>
#include <khz/reduced/errors.hpp>

#include <cmath>
#include <sstream>
#include <string>

namespace khz::reduced {

Eigen::MatrixXd weighted_modal_samples(const LinearModes& modes,
                                       const ModalDerivatives& derivatives,
                                       const SparseMatrix& mass) {
  const Eigen::Index k = modes.modes.cols();
  const Eigen::Index count = derivatives.vectors.cols();
  if (k < 1 || modes.eigenvalues.size() != k || mass.rows() != modes.modes.rows() ||
      mass.cols() != modes.modes.rows() || derivatives.vectors.rows() != modes.modes.rows() ||
      static_cast<Eigen::Index>(derivatives.pairs.size()) != count) {
    throw Error("weighted_modal_samples: the modes (" + std::to_string(modes.modes.rows()) + "×" +
                std::to_string(k) + "), derivatives (" +
                std::to_string(derivatives.vectors.rows()) + "×" + std::to_string(count) + ", " +
                std::to_string(derivatives.pairs.size()) + " pairs) and mass matrix (" +
                std::to_string(mass.rows()) + "×" + std::to_string(mass.cols()) +
                ") do not fit together");
  }
  const Eigen::VectorXd& lambda = modes.eigenvalues;
  Eigen::MatrixXd samples(modes.modes.rows(), k + count);
  for (Eigen::Index j = 0; j < k; ++j)
    samples.col(j) = (lambda(0) / lambda(j)) * modes.modes.col(j);
  for (Eigen::Index c = 0; c < count; ++c) {
    const auto [i, j] = derivatives.pairs[static_cast<std::size_t>(c)];
    if (i < 0 || j < 0 || i >= k || j >= k) {
      throw Error("weighted_modal_samples: derivative " + std::to_string(c) + " names mode pair (" +
                  std::to_string(i) + ", " + std::to_string(j) + ") outside the " +
                  std::to_string(k) + " modes");
    }
    const auto phi = derivatives.vectors.col(c);
    const double norm = std::sqrt(phi.dot(mass * phi));
    if (!(norm > 0.0) || !std::isfinite(norm)) {
      throw Error("weighted_modal_samples: derivative " + std::to_string(c) + " (" +
                  std::to_string(i) + ", " + std::to_string(j) + ") has mass norm " +
                  std::to_string(norm));
    }
    samples.col(k + c) = (lambda(0) * lambda(0) / (lambda(i) * lambda(j)) / norm) * phi;
  }
  return samples;
}

Basis modal_derivative_basis(const FemModel& model, std::span<const int> fixed_vertices,
                             const ModalDerivativeBasisOptions& options) {
  LinearModesOptions mode_options = options.modes;
  mode_options.progress = options.progress;
  const LinearModes modes = compute_linear_modes(model, fixed_vertices, mode_options);

  ModalDerivativesOptions derivative_options = options.derivatives;
  derivative_options.progress = options.progress;
  const ModalDerivatives derivatives = compute_modal_derivatives(model, modes, derivative_options);

  const SparseMatrix mass = model.mass_matrix(modes.mass);
  Eigen::MatrixXd samples = weighted_modal_samples(modes, derivatives, mass);
  if (modes.unconstrained()) {
    // Eq. 2.60's Φᵢⱼ (i ≠ j) carry infinitesimal rotations (ΨᵢᵀMΦᵢⱼ = 0 fixes only the Ψᵢ
    // part); those belong to the rigid frame, so keep the samples M-orthogonal to the rigid
    // modes (§2.8.7: rigid motion is coupled with the deformations separately).
    const Eigen::MatrixXd& rigid = modes.rigid_modes;
    samples -= rigid * (rigid.transpose() * (mass * samples));
  }
  PcaOptions pca;
  pca.basis_size = options.basis_size;
  pca.metric = options.metric;
  pca.progress = options.progress;
  Basis basis;
  basis.vectors = principal_components(samples, mass, pca).basis;
  basis.fixed_vertices = modes.fixed_vertices;
  detail::zero_fixed_rows(basis.vectors, basis.fixed_vertices);
  std::ostringstream recipe;
  recipe << "modal derivatives: k=" << modes.modes.cols() << " modes"
         << (modes.unconstrained() ? " (unconstrained, rigid modes excluded)" : "") << ", "
         << derivatives.vectors.cols() << " derivatives, " << detail::pca_name(options.metric)
         << " to r=" << basis.vectors.cols();
  basis.recipe = recipe.str();
  return basis;
}

}  // namespace khz::reduced
