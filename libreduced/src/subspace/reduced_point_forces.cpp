#include <khz/reduced/subspace/reduced_point_forces.hpp>

#include <cassert>

namespace khz::reduced {

bool reduced_point_forces(const Eigen::Ref<const Eigen::MatrixXd>& basis,
                          std::span<const PointForce> forces,
                          Eigen::Ref<Eigen::VectorXd> reduced_force) noexcept {
  assert(reduced_force.size() == basis.cols() && "the reduced force must have r entries");
  reduced_force.setZero();
  const Eigen::Index vertices = basis.rows() / 3;
  for (const PointForce& point : forces) {
    if (point.vertex < 0 || point.vertex >= vertices || !point.force.allFinite()) {
      reduced_force.setZero();
      return false;
    }
    reduced_force.noalias() +=
        basis.middleRows<3>(3 * Eigen::Index{point.vertex}).transpose() * point.force;
  }
  return true;
}

}  // namespace khz::reduced
