#include <khz/haptic/coupling/stiffness_bound.hpp>

#include <Eigen/SVD>

namespace khz::haptic {

double contact_stiffness(const Eigen::Matrix3d& force_by_translation) noexcept {
  return Eigen::JacobiSVD<Eigen::Matrix3d>(force_by_translation).singularValues()[0];
}

double rendered_stiffness_bound(double coupling_stiffness, double contact_stiffness) noexcept {
  // Series springs (eq. 4.30–4.31); written so that ‖J‖₂ = 0 gives 0 and ‖J‖₂ = ∞ gives k_VC.
  if (contact_stiffness <= 0.0) return 0.0;
  return 1.0 / (1.0 / contact_stiffness + 1.0 / coupling_stiffness);
}

}  // namespace khz::haptic
