#pragma once
// Reduced forces by direct projection of the full model: the reference, and the path for
// materials without polynomial forces.

#include <khz/reduced/export.hpp>
#include <khz/reduced/fem/fem_model.hpp>
#include <khz/reduced/subspace/reduced_forces.hpp>

#include <Eigen/Core>

namespace khz::reduced {

/// R̃(q) = UᵀR(Uq), K̃(q) = UᵀK(Uq)U and E(q) = W(Uq) evaluated through the full FEM model
/// (thesis eq. 2.23, 2.25; the approach of [KLM01] that §2.9 mentions for general materials).
/// Exact for any material the FemModel implements, but each evaluation costs Θ(n r²) (a full
/// assembly and a sparse-times-dense product), so it serves as the reference that the
/// polynomial evaluator is tested against, not as a haptic-rate path. Full-size workspaces are
/// allocated once; Eigen's dense products may still use temporary buffers for large r.
class KHZ_REDUCED_API ProjectedForces final : public ReducedForceModel {
 public:
  /// @param model the FEM model; must outlive this object.
  /// @param basis U, model.num_dofs() × r (copied).
  /// @throws Error if the basis has the wrong number of rows, no columns or non-finite entries.
  ProjectedForces(const FemModel& model, Eigen::MatrixXd basis);

  Eigen::Index dimension() const noexcept override { return m_basis.cols(); }
  void evaluate(const Eigen::Ref<const Eigen::VectorXd>& q, Eigen::Ref<Eigen::VectorXd> forces,
                Eigen::Ref<Eigen::MatrixXd> stiffness) noexcept override;
  void evaluate_forces(const Eigen::Ref<const Eigen::VectorXd>& q,
                       Eigen::Ref<Eigen::VectorXd> forces) noexcept override;
  double energy(const Eigen::Ref<const Eigen::VectorXd>& q) noexcept override;

 private:
  const FemModel& m_model;
  Eigen::MatrixXd m_basis;
  Eigen::VectorXd m_displacement;     // u = Uq
  Eigen::VectorXd m_full_forces;      // R(u)
  SparseMatrix m_full_stiffness;      // K(u), on the model's pattern
  Eigen::MatrixXd m_stiffness_basis;  // K(u) U
};

}  // namespace khz::reduced
