// The option tables of libhaptic's structs: the scene's coupling, loop and dynamics, and its
// devices.
#include "names.hpp"
#include "option_tables.hpp"

#include <array>

namespace khz::scene::detail {

template <>
const OptionTable<haptic::CouplingOptions>& option_table() {
  using O = haptic::CouplingOptions;
  // period is not a key: it is 1 / loop.rate_hz. Limits left out stay unlimited.
  static const OptionTable<O> table{
      number("stiffness", &O::stiffness, above(0.0)),
      number("torque_stiffness", &O::torque_stiffness, above(0.0)),
      number("static_damping", &O::static_damping, half_open(0.0, 1.0)),
      number("max_speed", &O::max_speed, above(0.0)),
      number("max_angular_speed", &O::max_angular_speed, above(0.0)),
      number("saturation_force", &O::saturation_force, above(0.0)),
      number("object_radius", &O::object_radius, above(0.0)),
      number("max_rendered_force", &O::max_rendered_force, above(0.0)),
      number("max_rendered_torque", &O::max_rendered_torque, above(0.0)),
      number("device_max_stiffness", &O::device_max_stiffness, above(0.0)),
      number("degenerate_threshold", &O::degenerate_threshold, open_interval(0.0, 1.0)),
      number("rotation_length", &O::rotation_length, at_least(0.0)),
  };
  return table;
}

template <>
const OptionTable<haptic::LoopOptions>& option_table() {
  using O = haptic::LoopOptions;
  // statistics_every is not a key: it is the tool's business.
  static const OptionTable<O> table{
      number("rate_hz", &O::rate_hz, open_closed(0.0, 100000.0)),
      flag("realtime_priority", &O::realtime_priority),
      integer("priority", &O::priority, closed(1, 99)),
      integer("cpu", &O::cpu, at_least(-1)),
  };
  return table;
}

template <>
const OptionTable<haptic::DynamicsOptions>& option_table() {
  using O = haptic::DynamicsOptions;
  // time_step is not a key: it is 1 / loop.rate_hz.
  static const OptionTable<O> table{
      vector3("gravity", &O::gravity),
      number("contact_damping", &O::contact_damping, at_least(0.0)),
      number("sleep_speed", &O::sleep_speed, at_least(0.0)),
      number("sleep_time", &O::sleep_time, at_least(0.0)),
  };
  return table;
}

template <>
const OptionTable<haptic::DeviceCapabilities>& option_table() {
  using O = haptic::DeviceCapabilities;
  // name is the device's own; nominal_rate is loop.rate_hz.
  static const OptionTable<O> table{
      integer_of("input_dof", &O::input_dof, std::array{3, 6}, "3 or 6"),
      integer_of("output_dof", &O::output_dof, std::array{0, 3, 6}, "0, 3 or 6"),
      number("max_force", &O::max_force, above(0.0)),
      number("max_torque", &O::max_torque, above(0.0)),
      number("max_stiffness", &O::max_stiffness, above(0.0)),
      vector3("workspace_min", &O::workspace_min),
      vector3("workspace_max", &O::workspace_max),
      number("workspace_radius", &O::workspace_radius, above(0.0)),
  };
  return table;
}

template <>
const OptionTable<haptic::WorkspaceMapping>& option_table() {
  using O = haptic::WorkspaceMapping;
  static const OptionTable<O> table{
      number("scale", &O::scale, above(0.0)),
      pose("offset", &O::offset),
      number("force_scale", &O::force_scale, above(0.0)),
      number("torque_scale", &O::torque_scale, above(0.0)),
  };
  return table;
}

template <>
const OptionTable<haptic::SafetyOptions>& option_table() {
  using O = haptic::SafetyOptions;
  static const OptionTable<O> table{
      number("max_force", &O::max_force, at_least(0.0)),
      number("max_torque", &O::max_torque, at_least(0.0)),
      number("deadline_tolerance", &O::deadline_tolerance, at_least(0.0)),
      integer("ramp_cycles", &O::ramp_cycles, at_least(0)),
      number("onset_force", &O::onset_force, at_least(0.0)),
      number("onset_torque", &O::onset_torque, at_least(0.0)),
      flag("passivity_control", &O::passivity_control),
      number("passivity_max_damping", &O::passivity_max_damping, above(0.0)),
      number("passivity_max_rotational_damping", &O::passivity_max_rotational_damping, above(0.0)),
      integer("index_button", &O::index_button, closed(-1, 31)),
      flag("index_orientation", &O::index_orientation),
      flag("zero_output_while_indexing", &O::zero_output_while_indexing),
  };
  return table;
}

template <>
const OptionTable<haptic::DeviceDynamics>& option_table() {
  using O = haptic::DeviceDynamics;
  static const OptionTable<O> table{
      number("mass", &O::mass, above(0.0)),
      number("inertia", &O::inertia, above(0.0)),
      number("damping", &O::damping, at_least(0.0)),
      number("rotational_damping", &O::rotational_damping, at_least(0.0)),
  };
  return table;
}

template <>
const OptionTable<haptic::HandModel>& option_table() {
  using O = haptic::HandModel;
  static const OptionTable<O> table{
      number("mass", &O::mass, above(0.0)),
      number("inertia", &O::inertia, above(0.0)),
      number("stiffness", &O::stiffness, at_least(0.0)),
      number("damping", &O::damping, at_least(0.0)),
      number("rotational_stiffness", &O::rotational_stiffness, at_least(0.0)),
      number("rotational_damping", &O::rotational_damping, at_least(0.0)),
  };
  return table;
}

template <>
const OptionTable<haptic::SimulatedOperatorOptions>& option_table() {
  using O = haptic::SimulatedOperatorOptions;
  // capabilities is the device's "capabilities" block, shared with the other device types.
  static const OptionTable<O> table{
      block("dynamics", &O::device, option_table<haptic::DeviceDynamics>()),
      block("hand", &O::hand, option_table<haptic::HandModel>()),
      integer("substeps", &O::substeps, at_least(1)),
      flag("start_at_target", &O::start_at_target),
      pose("initial_pose", &O::initial_pose),
  };
  return table;
}

template <>
const OptionTable<haptic::TrajectoryDeviceOptions>& option_table() {
  using O = haptic::TrajectoryDeviceOptions;
  // record_capacity is not a key: one pass is what a scene runs.
  static const OptionTable<O> table{
      choice("playback", &O::playback, playbacks),
  };
  return table;
}

}  // namespace khz::scene::detail
