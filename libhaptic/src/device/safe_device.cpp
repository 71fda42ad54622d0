#include <khz/haptic/device/safe_device.hpp>

#include "clamp_magnitude.hpp"
#include "device/pose_math.hpp"

#include <algorithm>
#include <cmath>
#include <string>

namespace khz::haptic {
namespace {

bool positive_finite(double value) noexcept { return std::isfinite(value) && value > 0.0; }

/// The events that make a write send zero (and restart the ramp from zero).
constexpr std::uint32_t zeroing_events =
    safety_zeroed_read_failure | safety_zeroed_invalid_output | safety_zeroed_indexing;

bool valid_reading(const DeviceState& state) noexcept {
  return detail::is_valid_pose(state.pose) && std::isfinite(state.time) &&
         (!state.has_linear_velocity || state.linear_velocity.allFinite()) &&
         (!state.has_angular_velocity || state.angular_velocity.allFinite());
}

}  // namespace

void WorkspaceMapping::validate() const {
  if (!positive_finite(scale)) throw Error("workspace mapping: scale must be finite and > 0");
  if (!positive_finite(force_scale) || !positive_finite(torque_scale)) {
    throw Error("workspace mapping: force_scale and torque_scale must be finite and > 0");
  }
  if (!detail::is_valid_pose(offset)) {
    throw Error("workspace mapping: the offset must be finite with a unit quaternion");
  }
}

void SafetyOptions::validate() const {
  if (std::isnan(max_force) || max_force < 0.0 || std::isnan(max_torque) || max_torque < 0.0) {
    throw Error("safety options: max_force and max_torque must be >= 0 (infinity for none)");
  }
  if (!std::isfinite(deadline_tolerance) || deadline_tolerance < 0.0) {
    throw Error("safety options: deadline_tolerance must be finite and >= 0 (s)");
  }
  if (ramp_cycles < 0) throw Error("safety options: ramp_cycles must be >= 0");
  if (std::isnan(onset_force) || onset_force < 0.0 || std::isnan(onset_torque) ||
      onset_torque < 0.0) {
    throw Error(
        "safety options: onset_force and onset_torque must be >= 0 (N, N m; infinity for no "
        "wait)");
  }
  if (!positive_finite(passivity_max_damping) ||
      !positive_finite(passivity_max_rotational_damping)) {
    throw Error(
        "safety options: passivity_max_damping (N s/m) and passivity_max_rotational_damping "
        "(N m s/rad) must be finite and > 0");
  }
  if (index_button < -1 || index_button > 31) {
    throw Error("safety options: index_button must be -1 (none) or a bit index in [0, 31], not " +
                std::to_string(index_button));
  }
}

SafeDevice::SafeDevice(Device& device, const SafetyOptions& options,
                       const WorkspaceMapping& mapping)
    : m_device(device) {
  set_options(options);
  set_mapping(mapping);
  restart();
}

void SafeDevice::open() {
  if (!m_device.is_open()) m_device.open();
  try {
    m_device.capabilities().validate();
  } catch (...) {
    m_device.close();
    throw;
  }
  update_limits();
  restart();
}

void SafeDevice::close() noexcept {
  if (m_device.is_open()) send(Wrench{}, 0);
  m_device.close();
  restart();
}

void SafeDevice::restart() noexcept {
  m_input_ok = false;
  m_indexing = false;
  m_cycle_open = false;
  m_pending_miss = false;
  m_ramp_step = 0;
  m_ramp_from = Wrench{};
  m_waiting_for_small_force = true;
  m_virtual_state.valid = false;
  m_passivity.restart();
}

void SafeDevice::update_limits() noexcept {
  const DeviceCapabilities& capabilities = m_device.capabilities();
  m_force_limit = std::min(m_options.max_force, capabilities.max_force);
  m_torque_limit =
      capabilities.output_dof < 6 ? 0.0 : std::min(m_options.max_torque, capabilities.max_torque);
}

void SafeDevice::set_options(const SafetyOptions& options) {
  options.validate();
  m_options = options;
  m_passivity.set_limits(options.passivity_max_damping, options.passivity_max_rotational_damping);
  update_limits();
}

void SafeDevice::set_mapping(const WorkspaceMapping& mapping) {
  mapping.validate();
  m_mapping = mapping;
  m_mapping.offset.orientation.normalize();
}

void SafeDevice::set_scale(double scale) {
  if (!positive_finite(scale)) throw Error("set_scale: the scale must be finite and > 0");
  if (m_input_ok && !m_indexing) {
    // Keep x_virtual = t + R s x_device where it is: t' = t + R (s - s') x_device.
    m_mapping.offset.position +=
        m_mapping.offset.orientation * ((m_mapping.scale - scale) * m_device_state.pose.position);
  }
  m_mapping.scale = scale;
}

bool SafeDevice::read(DeviceState& state) noexcept {
  ++m_statistics.reads;
  const bool device_ok = m_device.read(m_device_state) && m_device_state.valid;
  if (!device_ok || !valid_reading(m_device_state)) {
    ++(device_ok ? m_statistics.invalid_inputs : m_statistics.read_failures);
    m_input_ok = false;
    m_passivity.interrupt();
    state = m_virtual_state;
    state.valid = false;
    return false;
  }
  m_input_ok = true;
  DeviceState& device = m_device_state;
  device.pose.orientation.normalize();
  m_passivity.observe(device.pose, device.time, m_last_output,
                      1.0 / m_device.capabilities().nominal_rate);

  const bool held =
      m_options.index_button >= 0 && ((device.buttons >> m_options.index_button) & 1u) != 0;
  if (!held && m_indexing) {
    // Release: move the offset so the device's current pose maps onto the frozen virtual pose.
    if (m_options.index_orientation) {
      m_mapping.offset.orientation =
          (m_frozen.orientation * device.pose.orientation.conjugate()).normalized();
    }
    m_mapping.offset.position =
        m_frozen.position - m_mapping.offset.orientation * (m_mapping.scale * device.pose.position);
    m_indexing = false;
  }

  const Eigen::Quaterniond& rotation = m_mapping.offset.orientation;
  DeviceState mapped = device;
  mapped.pose.position =
      m_mapping.offset.position + rotation * (m_mapping.scale * device.pose.position);
  mapped.pose.orientation = (rotation * device.pose.orientation).normalized();
  mapped.linear_velocity = m_mapping.scale * (rotation * device.linear_velocity);
  mapped.angular_velocity = rotation * device.angular_velocity;
  mapped.valid = true;

  if (held) {
    // Freeze where the tool was before the press: motion in the press cycle is already indexed.
    if (!m_indexing) m_frozen = m_virtual_state.valid ? m_virtual_state.pose : mapped.pose;
    m_indexing = true;
    ++m_statistics.indexed_cycles;
    mapped.pose.position = m_frozen.position;
    mapped.linear_velocity.setZero();
    if (m_options.index_orientation) {
      mapped.pose.orientation = m_frozen.orientation;
      mapped.angular_velocity.setZero();
    }
  }
  m_virtual_state = mapped;
  state = mapped;
  return true;
}

bool SafeDevice::write(const Wrench& wrench, const Wrench& pending) noexcept {
  std::uint32_t events = 0;
  if (!m_input_ok) events |= safety_zeroed_read_failure;
  if (m_pending_miss) {
    // The late cycle's output is what the hand has been feeling: start from it.
    events |= safety_after_deadline_miss;
    m_ramp_from = m_last_output;
    m_ramp_step = 0;
  }
  m_pending_miss = false;
  if (m_indexing && m_options.zero_output_while_indexing) events |= safety_zeroed_indexing;

  const Eigen::Quaterniond inverse = m_mapping.offset.orientation.conjugate();
  Wrench output;
  output.force = m_mapping.force_scale * (inverse * wrench.force);
  output.torque = m_mapping.torque_scale * (inverse * wrench.torque);
  if (!detail::is_finite(output)) {
    ++m_statistics.invalid_outputs;
    events |= safety_zeroed_invalid_output;
  }
  if ((events & zeroing_events) != 0) return send(Wrench{}, events);

  if (m_waiting_for_small_force) {
    // Each is small when within its threshold (infinity: always); NaN never is.
    const auto small = [](double asked, double coming, double onset) {
      return std::isinf(onset) || (asked <= onset && coming <= onset);
    };
    const bool force_small =
        small(detail::magnitude(output.force),
              m_mapping.force_scale * detail::magnitude(pending.force), m_options.onset_force);
    const bool torque_small =
        m_device.capabilities().output_dof < 6 ||
        small(detail::magnitude(output.torque),
              m_mapping.torque_scale * detail::magnitude(pending.torque), m_options.onset_torque);
    if (!force_small || !torque_small) {
      return send(Wrench{}, safety_waiting_for_small_force);
    }
    m_waiting_for_small_force = false;
  }
  if (m_options.passivity_control && m_passivity.damp(output)) {
    events |= safety_passivity_damping;
    ++m_statistics.passivity_damped_writes;
  }
  const int output_dof = m_device.capabilities().output_dof;
  if (output_dof == 0) output.force.setZero();
  if (output_dof < 6) output.torque.setZero();
  if (detail::clamp_magnitude(output.force, m_force_limit)) events |= safety_clamped_force;
  if (detail::clamp_magnitude(output.torque, m_torque_limit)) events |= safety_clamped_torque;
  if (m_ramp_step < m_options.ramp_cycles) {
    ++m_ramp_step;
    const double factor = double(m_ramp_step) / double(m_options.ramp_cycles);
    if (factor < 1.0) events |= safety_ramping;
    output.force = m_ramp_from.force + factor * (output.force - m_ramp_from.force);
    output.torque = m_ramp_from.torque + factor * (output.torque - m_ramp_from.torque);
  }
  return send(output, events);
}

bool SafeDevice::send(const Wrench& output, std::uint32_t events) noexcept {
  if ((events & zeroing_events) != 0) {
    m_ramp_step = 0;
    m_ramp_from = Wrench{};
    // A device that failed may come back anywhere, inside an object: wait for a small force.
    // An indexing pause leaves the pose continuous: only the ramp applies.
    if ((events & safety_zeroed_read_failure) != 0) m_waiting_for_small_force = true;
    if ((events & ~safety_zeroed_indexing & zeroing_events) != 0) ++m_statistics.zeroed_writes;
  }
  if ((events & (safety_clamped_force | safety_clamped_torque)) != 0) {
    ++m_statistics.clamped_writes;
  }
  ++m_statistics.writes;
  m_last_output = output;
  m_last_events = events;
  const bool sent = m_device.write(output);
  if (!sent) ++m_statistics.device_write_failures;
  return sent;
}

void SafeDevice::begin_cycle(double deadline) noexcept {
  m_deadline = deadline;
  m_cycle_open = true;
}

void SafeDevice::end_cycle(double now) noexcept {
  if (!m_cycle_open) return;
  m_cycle_open = false;
  if (!(now <= m_deadline + m_options.deadline_tolerance)) {  // NaN counts as late
    ++m_statistics.deadline_misses;
    m_pending_miss = true;
  }
}

}  // namespace khz::haptic
