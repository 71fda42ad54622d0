#pragma once
// The cross-product matrix, which the contact gradients (§4.2) are written in.

#include <Eigen/Core>

namespace khz::contact::detail {

/// The cross-product matrix ã of a: ã b = a × b.
inline Eigen::Matrix3d cross_matrix(const Eigen::Vector3d& a) noexcept {
  Eigen::Matrix3d m;
  m << 0.0, -a.z(), a.y(), a.z(), 0.0, -a.x(), -a.y(), a.x(), 0.0;
  return m;
}

}  // namespace khz::contact::detail
