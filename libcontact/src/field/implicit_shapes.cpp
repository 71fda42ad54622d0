#include <khz/contact/field/implicit_shapes.hpp>

#include <string>
#include <utility>

namespace khz::contact {

ImplicitShape::ImplicitShape(ImplicitPrimitive primitive, const Eigen::Isometry3d& pose)
    : m_primitive(std::move(primitive)),
      m_rotation(pose.linear()),
      m_translation(pose.translation()) {
  if (!m_rotation.allFinite() || !m_translation.allFinite()) {
    throw Error("ImplicitShape: the pose is not finite");
  }
  const double orthonormality =
      (m_rotation.transpose() * m_rotation - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
  if (orthonormality > 1e-9 || m_rotation.determinant() < 0.0) {
    throw Error("ImplicitShape: the pose's linear part is not a rotation (|RᵀR − I| = " +
                std::to_string(orthonormality) +
                ", det R = " + std::to_string(m_rotation.determinant()) + ")");
  }
}

Eigen::Isometry3d ImplicitShape::pose() const noexcept {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = m_rotation;
  pose.translation() = m_translation;
  return pose;
}

ImplicitUnion::ImplicitUnion(std::vector<ImplicitShape> shapes) : m_shapes(std::move(shapes)) {
  if (m_shapes.empty()) throw Error("ImplicitUnion: no shape");
}

}  // namespace khz::contact
