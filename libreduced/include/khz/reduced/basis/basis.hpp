#pragma once
// The reduced basis U: the deformations a reduced model can represent, u = U q (thesis §2.2).

#include <Eigen/Core>

#include <string>
#include <vector>

namespace khz::reduced {

/// A reduced basis of a volume mesh: r deformation vectors on its full dofs, together with the
/// anchors they respect and how they were made. Produced by the basis generators
/// (modal_derivative_basis, sketch_basis, simulation_data_basis) and stored in basis files.
struct Basis {
  /// U, 3n × r (metres per unit of q): mass-orthonormal (UᵀMU = I) for the generators'
  /// output; zero rows at fixed vertices.
  Eigen::MatrixXd vectors;
  /// Vertices held fixed (sorted, distinct); empty for an unconstrained object.
  std::vector<int> fixed_vertices;
  /// Provenance in one line, e.g. "modal derivatives: k=20 modes, 210 derivatives, mass PCA
  /// to r=30"; informational only.
  std::string recipe;

  /// r, the number of basis vectors.
  Eigen::Index size() const noexcept { return vectors.cols(); }
};

}  // namespace khz::reduced
