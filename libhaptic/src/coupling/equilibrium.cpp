#include <khz/haptic/coupling/equilibrium.hpp>

#include "coupling/one_sided_jacobi.hpp"

#include <Eigen/LU>

namespace khz::haptic {

EquilibriumSystem equilibrium_system(const CouplingWrench& coupling,
                                     const contact::ContactWrench& contact) noexcept {
  EquilibriumSystem system;
  system.jacobian.topLeftCorner<3, 3>() =
      coupling.force_by_translation + contact.force_by_translation;
  system.jacobian.topRightCorner<3, 3>() = contact.force_by_rotation;
  system.jacobian.bottomLeftCorner<3, 3>() = contact.torque_by_translation;
  system.jacobian.bottomRightCorner<3, 3>() =
      coupling.torque_by_rotation + contact.torque_by_rotation;
  system.net_wrench.head<3>() = coupling.force + contact.force;
  system.net_wrench.tail<3>() = coupling.torque + contact.torque;
  return system;
}

EquilibriumSolution solve_equilibrium(const Matrix6d& a, const Vector6d& b, const Vector6d& target,
                                      double epsilon) noexcept {
  // A = W Vᵀ, wᵢ = σᵢ uᵢ: uᵢᵀb / σᵢ = wᵢᵀb / σᵢ².
  const detail::ScaledSvd svd = detail::one_sided_jacobi(a);
  const Vector6d& sigma = svd.sigma;
  const Matrix6d& v = svd.v;
  const double threshold = epsilon * sigma.maxCoeff();
  EquilibriumSolution solution;
  for (int i = 0; i < 6; ++i) {
    if (sigma[i] > 0.0 && sigma[i] >= threshold) {
      solution.step += (svd.w.col(i).dot(b) / sigma[i] / sigma[i]) * v.col(i);
    } else {
      solution.step += v.col(i).dot(target) * v.col(i);
      ++solution.degenerate_dimension;
    }
  }
  return solution;
}

Vector6d solve_equilibrium_lu(const Matrix6d& a, const Vector6d& b) noexcept {
  return Eigen::PartialPivLU<Matrix6d>(a).solve(b);
}

}  // namespace khz::haptic
