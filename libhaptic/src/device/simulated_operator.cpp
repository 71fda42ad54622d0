#include <khz/haptic/device/simulated_operator.hpp>

#include <khz/haptic/coupling/rotation_vector.hpp>

#include "clamp_magnitude.hpp"
#include "device/pose_math.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <utility>

namespace khz::haptic {
namespace {

void require(bool condition, const std::string& message) {
  if (!condition) throw Error("simulated operator: " + message);
}

bool non_negative(double value) noexcept { return std::isfinite(value) && value >= 0.0; }
bool positive(double value) noexcept { return std::isfinite(value) && value > 0.0; }

/// Semi-implicit Euler on m ẍ + b ẋ + k x = 0 is stable iff h² k/m + 2 h b/m < 4.
void require_stable(double h, double inertia, double stiffness, double damping,
                    const std::string& what) {
  const double bound = h * h * stiffness / inertia + 2.0 * h * damping / inertia;
  require(bound < 4.0, what + ": h² k/m + 2 h b/m = " + std::to_string(bound) +
                           " must be < 4 for a stable step at h = " + std::to_string(h) +
                           " s (raise the rate, lower the stiffness or damping, or add mass)");
}

}  // namespace

DeviceCapabilities SimulatedOperatorOptions::phantom_premium_like() {
  DeviceCapabilities capabilities;
  capabilities.name = "simulated operator (Phantom Premium 1.5 6-DOF-like)";
  capabilities.max_force = 8.5;  // 6-DOF in and out and 1 kHz are the defaults
  capabilities.max_torque = 0.5;
  capabilities.max_stiffness = 3500.0;
  capabilities.workspace_max = Eigen::Vector3d(0.19, 0.135, 0.095);
  capabilities.workspace_min = -capabilities.workspace_max;
  return capabilities;
}

void SimulatedOperatorOptions::validate() const {
  capabilities.validate();
  require(positive(device.mass) && positive(device.inertia),
          "the device's mass and inertia must be finite and > 0");
  require(non_negative(hand.mass) && non_negative(hand.inertia),
          "the hand's mass and inertia must be finite and >= 0");
  require(non_negative(device.damping) && non_negative(device.rotational_damping) &&
              non_negative(hand.stiffness) && non_negative(hand.damping) &&
              non_negative(hand.rotational_stiffness) && non_negative(hand.rotational_damping),
          "stiffnesses and dampings must be finite and >= 0");
  require(detail::is_valid_pose(initial_pose), "the initial pose must be finite and unit");
  require(substeps >= 1, "substeps must be >= 1");
  const double h = 1.0 / (capabilities.nominal_rate * substeps);
  require_stable(h, device.mass + hand.mass, hand.stiffness, hand.damping + device.damping,
                 "translation");
  require_stable(h, device.inertia + hand.inertia, hand.rotational_stiffness,
                 hand.rotational_damping + device.rotational_damping, "rotation");
}

namespace {

/// Keyframes checked for keyframe_target() and keyframe_buttons(), orientations normalised.
std::vector<Keyframe> checked_keyframes(std::vector<Keyframe> keyframes) {
  require(!keyframes.empty(), "keyframe_target needs at least one keyframe");
  for (std::size_t i = 0; i < keyframes.size(); ++i) {
    require(std::isfinite(keyframes[i].time) &&
                (i == 0 || keyframes[i].time > keyframes[i - 1].time) &&
                detail::is_valid_pose(keyframes[i].pose),
            "keyframe " + std::to_string(i) +
                " has a non-finite or non-increasing time or an invalid pose");
    keyframes[i].pose.orientation.normalize();
  }
  return keyframes;
}

}  // namespace

TargetFunction keyframe_target(std::vector<Keyframe> keyframes) {
  return [frames = checked_keyframes(std::move(keyframes))](double time) {
    if (!(time > frames.front().time)) return frames.front().pose;
    if (time >= frames.back().time) return frames.back().pose;
    std::size_t i = 1;
    while (frames[i].time < time) ++i;  // frames[i - 1].time < time <= frames[i].time
    const Keyframe& a = frames[i - 1];
    const Keyframe& b = frames[i];
    const double u = (time - a.time) / (b.time - a.time);
    Pose pose;
    pose.position = (1.0 - u) * a.pose.position + u * b.pose.position;
    pose.orientation = a.pose.orientation.slerp(u, b.pose.orientation);
    return pose;
  };
}

ButtonFunction keyframe_buttons(std::vector<Keyframe> keyframes) {
  keyframes = checked_keyframes(std::move(keyframes));
  if (std::none_of(keyframes.begin(), keyframes.end(),
                   [](const Keyframe& frame) { return frame.buttons != 0; })) {
    return {};
  }
  return [frames = std::move(keyframes)](double time) {
    std::uint32_t buttons = 0;
    for (const Keyframe& frame : frames) {
      if (frame.time > time) break;
      buttons = frame.buttons;
    }
    return buttons;
  };
}

SimulatedOperator::SimulatedOperator(TargetFunction target, const SimulatedOperatorOptions& options,
                                     ButtonFunction buttons)
    : m_target(std::move(target)), m_options(options), m_buttons(std::move(buttons)) {
  m_options.validate();
  require(static_cast<bool>(m_target), "the target function is empty");
  m_step = 1.0 / (m_options.capabilities.nominal_rate * m_options.substeps);
}

void SimulatedOperator::open() {
  m_time = 0.0;
  m_steps = 0;
  m_previous_target = m_target(0.0);
  m_pose = m_options.start_at_target ? m_previous_target : m_options.initial_pose;
  m_pose.orientation.normalize();
  m_linear_velocity.setZero();
  m_angular_velocity.setZero();
  m_applied = Wrench{};
  m_invalid_reads = 0;
  m_disconnected_reads = 0;
  m_stalled_periods = 0;
  m_connected = true;
  m_started = false;
  m_open = true;
}

void SimulatedOperator::close() noexcept {
  m_applied = Wrench{};
  m_open = false;
}

void SimulatedOperator::inject_disconnect(int reads) noexcept {
  m_disconnected_reads = reads;
  if (reads > 0) {
    m_connected = false;
    m_applied = Wrench{};
  }
}

void SimulatedOperator::step() noexcept {
  const double h = m_step;
  const DeviceDynamics& device = m_options.device;
  const HandModel& hand = m_options.hand;
  const Pose target = m_target(m_time);
  const Eigen::Vector3d target_velocity = (target.position - m_previous_target.position) / h;
  const Eigen::Vector3d target_angular_velocity =
      rotation_vector(target.orientation * m_previous_target.orientation.conjugate()) / h;
  m_previous_target = target;

  const Eigen::Vector3d force = hand.stiffness * (target.position - m_pose.position) +
                                hand.damping * (target_velocity - m_linear_velocity) -
                                device.damping * m_linear_velocity + m_applied.force;
  const Eigen::Vector3d torque =
      hand.rotational_stiffness *
          rotation_vector(target.orientation * m_pose.orientation.conjugate()) +
      hand.rotational_damping * (target_angular_velocity - m_angular_velocity) -
      device.rotational_damping * m_angular_velocity + m_applied.torque;

  m_linear_velocity += (h / (device.mass + hand.mass)) * force;
  m_pose.position += h * m_linear_velocity;
  m_angular_velocity += (h / (device.inertia + hand.inertia)) * torque;
  m_pose.orientation =
      (rotation_quaternion(h * m_angular_velocity) * m_pose.orientation).normalized();
  ++m_steps;
  m_time = double(m_steps) * h;  // no drift from repeated addition
}

bool SimulatedOperator::read(DeviceState& state) noexcept {
  if (!m_open) {
    state.valid = false;
    return false;
  }
  if (m_started) {
    for (int period = 0; period <= m_stalled_periods; ++period) {
      for (int s = 0; s < m_options.substeps; ++s) step();
    }
    m_stalled_periods = 0;
  }
  m_started = true;
  m_connected = m_disconnected_reads == 0;
  if (!m_connected) {
    --m_disconnected_reads;
    state.valid = false;
    return false;
  }
  const bool six_dof = m_options.capabilities.input_dof == 6;
  state.pose.position = m_pose.position;
  state.pose.orientation = six_dof ? m_pose.orientation : Eigen::Quaterniond::Identity();
  state.linear_velocity = m_linear_velocity;
  state.angular_velocity = six_dof ? m_angular_velocity : Eigen::Vector3d::Zero();
  state.has_linear_velocity = true;
  state.has_angular_velocity = six_dof;
  state.buttons = m_buttons ? m_buttons(m_time) : 0u;
  state.time = m_time;
  state.valid = true;
  if (m_invalid_reads > 0) {
    --m_invalid_reads;
    state.pose.position.setConstant(std::numeric_limits<double>::quiet_NaN());
  }
  return true;
}

bool SimulatedOperator::write(const Wrench& wrench) noexcept {
  if (!m_open || !m_connected) return false;
  if (!detail::is_finite(wrench)) {
    ++m_rejected_writes;
    m_applied = Wrench{};
    return false;
  }
  const DeviceCapabilities& capabilities = m_options.capabilities;
  m_applied = wrench;
  if (capabilities.output_dof == 0) m_applied.force.setZero();
  if (capabilities.output_dof < 6) m_applied.torque.setZero();
  detail::clamp_magnitude(m_applied.force, capabilities.max_force);
  detail::clamp_magnitude(m_applied.torque, capabilities.max_torque);
  return true;
}

double SimulatedOperator::kinetic_energy() const noexcept {
  const double mass = m_options.device.mass + m_options.hand.mass;
  const double inertia = m_options.device.inertia + m_options.hand.inertia;
  return 0.5 * mass * m_linear_velocity.squaredNorm() +
         0.5 * inertia * m_angular_velocity.squaredNorm();
}

double SimulatedOperator::hand_energy() const {
  const Pose target = m_target(m_time);
  const Eigen::Vector3d angle =
      rotation_vector(target.orientation * m_pose.orientation.conjugate());
  return 0.5 * m_options.hand.stiffness * (target.position - m_pose.position).squaredNorm() +
         0.5 * m_options.hand.rotational_stiffness * angle.squaredNorm();
}

}  // namespace khz::haptic
