#include <khz/reduced/errors.hpp>
#include <khz/reduced/subspace/projected_forces.hpp>

#include <string>
#include <utility>

namespace khz::reduced {

ProjectedForces::ProjectedForces(const FemModel& model, Eigen::MatrixXd basis)
    : m_model(model),
      m_basis(std::move(basis)),
      m_displacement(model.num_dofs()),
      m_full_forces(model.num_dofs()),
      m_full_stiffness(model.stiffness_pattern()),
      m_stiffness_basis(model.num_dofs(), m_basis.cols()) {
  if (m_basis.rows() != model.num_dofs()) {
    throw Error("ProjectedForces: the basis has " + std::to_string(m_basis.rows()) +
                " rows but the FEM model has " + std::to_string(model.num_dofs()) + " dofs");
  }
  if (m_basis.cols() == 0) throw Error("ProjectedForces: the basis has no vectors");
  if (!m_basis.allFinite()) throw Error("ProjectedForces: the basis has a non-finite entry");
}

// The FemModel calls below throw only for wrong sizes, which the constructor rules out.
void ProjectedForces::evaluate(const Eigen::Ref<const Eigen::VectorXd>& q,
                               Eigen::Ref<Eigen::VectorXd> forces,
                               Eigen::Ref<Eigen::MatrixXd> stiffness) noexcept {
  m_displacement.noalias() = m_basis * q;
  m_model.forces_and_stiffness(m_displacement, m_full_forces, m_full_stiffness);
  forces.noalias() = m_basis.transpose() * m_full_forces;
  m_stiffness_basis.noalias() = m_full_stiffness * m_basis;
  stiffness.noalias() = m_basis.transpose() * m_stiffness_basis;
  // Round-off leaves UᵀKU asymmetric in the last bits; callers rely on exact symmetry.
  for (Eigen::Index j = 0; j < stiffness.cols(); ++j) {
    for (Eigen::Index i = 0; i < j; ++i) {
      stiffness(i, j) = stiffness(j, i) = 0.5 * (stiffness(i, j) + stiffness(j, i));
    }
  }
}

void ProjectedForces::evaluate_forces(const Eigen::Ref<const Eigen::VectorXd>& q,
                                      Eigen::Ref<Eigen::VectorXd> forces) noexcept {
  m_displacement.noalias() = m_basis * q;
  m_model.internal_forces(m_displacement, m_full_forces);
  forces.noalias() = m_basis.transpose() * m_full_forces;
}

double ProjectedForces::energy(const Eigen::Ref<const Eigen::VectorXd>& q) noexcept {
  m_displacement.noalias() = m_basis * q;
  return m_model.strain_energy(m_displacement);
}

}  // namespace khz::reduced
