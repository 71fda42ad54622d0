#pragma once
// The generalized eigenproblem K(0) ψ = λ M ψ on the dofs the modes live on, shared by the
// linear modes and the modal derivatives (thesis §2.8.3, §2.8.7).

#include <khz/reduced/fem/fem_model.hpp>
#include <khz/reduced/solvers/fixed_dofs.hpp>
#include <khz/reduced/solvers/sparse_cholesky.hpp>
#include <khz/reduced/solvers/symmetric_factorization.hpp>

#include <Eigen/Core>

#include <memory>
#include <span>
#include <vector>

namespace khz::reduced::detail {

/// K(0) and M restricted to the free dofs (all dofs when nothing is fixed), and the shift σ
/// for which K − σM is positive definite: 0 when anchored, slightly negative when not.
class ModalProblem {
 public:
  /// @throws Error for a fixed vertex out of range; MeshError for a vertex in no element
  ///         (its mass is zero, so M is singular).
  ModalProblem(const FemModel& model, std::span<const int> fixed_vertices, MassLumping lumping);

  const FixedDofs& dofs() const noexcept { return m_dofs; }
  /// Sorted, distinct fixed vertices.
  const std::vector<int>& fixed_vertices() const noexcept { return m_fixed; }
  bool unconstrained() const noexcept { return m_fixed.empty(); }
  const SparseMatrix& stiffness() const noexcept { return m_stiffness; }
  const SparseMatrix& mass() const noexcept { return m_mass; }
  double shift() const noexcept { return m_shift; }

  /// LLᵀ factorization of K − σM.
  /// @throws SolverError if it is not positive definite; for an anchored object the message
  ///         says the anchors leave a rigid motion.
  SparseCholesky factorize_shifted() const;
  /// K − σM made with `factorize`, or by factorize_shifted() when it is empty.
  /// @throws SolverError as factorize_shifted(), or what `factorize` throws.
  std::unique_ptr<SymmetricFactorization> factorize_shifted(const Factorize& factorize) const;

 private:
  std::vector<int> m_fixed;
  FixedDofs m_dofs;
  SparseMatrix m_stiffness;
  SparseMatrix m_mass;
  double m_shift = 0.0;
};

/// Number of connected components of the mesh's element graph.
Eigen::Index count_components(const VolumeMesh& mesh);

/// The 6 rigid motions (3 translations, 3 infinitesimal rotations about the centroid) of each
/// connected component, 3n × 6c, not orthonormalized.
Eigen::MatrixXd rigid_motions(const VolumeMesh& mesh);

}  // namespace khz::reduced::detail
