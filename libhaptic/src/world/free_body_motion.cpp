#include <khz/haptic/common.hpp>
#include <khz/haptic/coupling/rotation_vector.hpp>
#include <khz/haptic/world/free_body_motion.hpp>

#include <Eigen/LU>

#include <cmath>
#include <string>

namespace khz::haptic {

void RigidInertia::validate() const {
  if (!(std::isfinite(mass) && mass > 0.0)) {
    throw Error("RigidInertia: mass must be finite and > 0 (kg), got " + std::to_string(mass));
  }
  if (!centre.allFinite()) throw Error("RigidInertia: the centre of mass is not finite");
  if (!inertia.allFinite() || (inertia - inertia.transpose()).norm() > 1e-9 * inertia.norm()) {
    throw Error("RigidInertia: the inertia tensor must be finite and symmetric");
  }
  if (inertia.llt().info() != Eigen::Success) {
    throw Error("RigidInertia: the inertia tensor must be positive definite (kg·m²)");
  }
}

FreeBodyMotion::FreeBodyMotion(const RigidInertia& inertia, const Eigen::Isometry3d& pose,
                               const Eigen::Vector3d& velocity,
                               const Eigen::Vector3d& angular_velocity)
    : m_inertia(inertia),
      m_pose(Eigen::Isometry3d::Identity()),
      m_inverse_inertia(Eigen::Matrix3d::Identity()),
      m_velocity(Eigen::Vector3d::Zero()),
      m_spin(Eigen::Vector3d::Zero()) {
  inertia.validate();
  m_inverse_inertia = inertia.inertia.inverse();
  if (!set_state(pose, velocity, angular_velocity)) {
    throw Error("FreeBodyMotion: the pose and velocities must be finite");
  }
}

bool FreeBodyMotion::set_state(const Eigen::Isometry3d& pose, const Eigen::Vector3d& velocity,
                               const Eigen::Vector3d& angular_velocity) noexcept {
  if (!pose.matrix().allFinite() || !velocity.allFinite() || !angular_velocity.allFinite()) {
    return false;
  }
  m_pose = pose;
  m_velocity = velocity;
  m_spin = world_inertia() * angular_velocity;
  return true;
}

Eigen::Matrix3d FreeBodyMotion::world_inertia() const noexcept {
  const Eigen::Matrix3d rotation = m_pose.linear();
  return rotation * m_inertia.inertia * rotation.transpose();
}

Eigen::Vector3d FreeBodyMotion::angular_velocity() const noexcept {
  const Eigen::Matrix3d rotation = m_pose.linear();
  return rotation * (m_inverse_inertia * (rotation.transpose() * m_spin));
}

double FreeBodyMotion::kinetic_energy() const noexcept {
  return 0.5 * m_inertia.mass * m_velocity.squaredNorm() + 0.5 * angular_velocity().dot(m_spin);
}

Eigen::Vector3d FreeBodyMotion::angular_momentum() const noexcept {
  return centre().cross(momentum()) + m_spin;
}

bool FreeBodyMotion::step(double h, const Eigen::Vector3d& force, const Eigen::Vector3d& torque,
                          const Eigen::Matrix<double, 6, 6>& stiffness,
                          const Eigen::Vector3d& gravity) noexcept {
  if (!(h > 0.0 && std::isfinite(h)) || !force.allFinite() || !torque.allFinite() ||
      !stiffness.allFinite() || !gravity.allFinite()) {
    return false;
  }
  const Eigen::Matrix3d inertia = world_inertia();
  const Eigen::Vector3d omega = angular_velocity();
  Eigen::Matrix<double, 6, 6> matrix = -h * h * stiffness;
  matrix.topLeftCorner<3, 3>().diagonal().array() += m_inertia.mass;
  matrix.bottomRightCorner<3, 3>() += inertia;
  Eigen::Matrix<double, 6, 1> u;
  u << m_velocity, omega;
  Eigen::Matrix<double, 6, 1> f;
  f << force + m_inertia.mass * gravity, torque;
  const Eigen::Matrix<double, 6, 1> rhs = h * (f + h * (stiffness * u));
  const Eigen::PartialPivLU<Eigen::Matrix<double, 6, 6>> lu(matrix);
  if (!(std::abs(lu.determinant()) > 0.0)) return false;
  const Eigen::Matrix<double, 6, 1> change = lu.solve(rhs);
  if (!change.allFinite()) return false;
  const Eigen::Vector3d velocity = m_velocity + change.head<3>();
  const Eigen::Vector3d centre_next = centre() + h * velocity;
  const Eigen::Quaterniond turn = rotation_quaternion(h * (omega + change.tail<3>()));
  const Eigen::Matrix3d rotation =
      (turn * Eigen::Quaterniond(m_pose.linear())).normalized().toRotationMatrix();
  m_spin += inertia * change.tail<3>();
  m_velocity = velocity;
  m_pose.linear() = rotation;
  m_pose.translation() = centre_next - rotation * m_inertia.centre;
  return true;
}

}  // namespace khz::haptic
