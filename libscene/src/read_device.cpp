#include "read_device.hpp"

#include "names.hpp"

#include <khz/haptic/device/null_device.hpp>

#include <string>

namespace khz::scene::detail {
namespace {

std::vector<haptic::Keyframe> read_keyframes(const ObjectReader& device) {
  const Json& value =
      device.required("keyframes", "the hand's target: [{\"time\", \"position\", \"rotation\"}]");
  const Location at = device.at("keyframes");
  if (!value.is_array() || value.empty()) {
    at.expected("a non-empty array of keyframes [{\"time\", \"position\", \"rotation\"}]", value);
  }
  std::vector<haptic::Keyframe> result;
  for (std::size_t i = 0; i < value.size(); ++i) {
    const ObjectReader keyframe(value[i], at.element(i), {"time", "position", "rotation"},
                                {{"t", "time"}});
    haptic::Keyframe frame;
    if (i == 0) {
      frame.time = keyframe.required_number("time", any_value(), "s");
    } else {
      const double previous = result.back().time;
      frame.time = keyframe.required_number(
          "time",
          with_text(above(previous), "a time after keyframes[" + std::to_string(i - 1) +
                                         "].time = " + format_number(previous) + " s"),
          "s");
    }
    frame.pose.position = keyframe.required_vector3("position", "[x, y, z] in m");
    if (keyframe.has("rotation")) {
      frame.pose.orientation = read_rotation(keyframe.value("rotation"), keyframe.at("rotation"));
    }
    result.push_back(frame);
  }
  return result;
}

void read_operator(const ObjectReader& device, haptic::SimulatedOperatorOptions& options) {
  if (const auto dynamics =
          device.object("dynamics", {"mass", "inertia", "damping", "rotational_damping"})) {
    haptic::DeviceDynamics& d = options.device;
    d.mass = dynamics->number("mass", d.mass, above(0.0));
    d.inertia = dynamics->number("inertia", d.inertia, above(0.0));
    d.damping = dynamics->number("damping", d.damping, at_least(0.0));
    d.rotational_damping =
        dynamics->number("rotational_damping", d.rotational_damping, at_least(0.0));
  }
  if (const auto hand = device.object("hand", {"mass", "inertia", "stiffness", "damping",
                                               "rotational_stiffness", "rotational_damping"})) {
    haptic::HandModel& h = options.hand;
    h.mass = hand->number("mass", h.mass, above(0.0));
    h.inertia = hand->number("inertia", h.inertia, above(0.0));
    h.stiffness = hand->number("stiffness", h.stiffness, at_least(0.0));
    h.damping = hand->number("damping", h.damping, at_least(0.0));
    h.rotational_stiffness =
        hand->number("rotational_stiffness", h.rotational_stiffness, at_least(0.0));
    h.rotational_damping = hand->number("rotational_damping", h.rotational_damping, at_least(0.0));
  }
  options.substeps = device.integer("substeps", options.substeps, at_least(1));
  options.start_at_target = device.boolean("start_at_target", options.start_at_target);
  if (device.has("initial_pose")) {
    options.initial_pose = read_pose(device.value("initial_pose"), device.at("initial_pose"));
  }
}

void read_capabilities(const ObjectReader& device, haptic::DeviceCapabilities& capabilities) {
  const auto given =
      device.object("capabilities",
                    {"input_dof", "output_dof", "max_force", "max_torque", "max_stiffness",
                     "workspace_min", "workspace_max", "workspace_radius"},
                    {{"nominal_rate", "loop.rate_hz"}});
  if (!given) return;
  haptic::DeviceCapabilities& c = capabilities;
  c.input_dof = given->integer("input_dof", c.input_dof, with_text(closed(3, 6), "3 or 6"));
  if (c.input_dof != 3 && c.input_dof != 6)
    given->at("input_dof").expected("3 or 6", given->value("input_dof"));
  c.output_dof = given->integer("output_dof", c.output_dof, with_text(closed(0, 6), "0, 3 or 6"));
  if (c.output_dof % 3 != 0)
    given->at("output_dof").expected("0, 3 or 6", given->value("output_dof"));
  c.max_force = given->number("max_force", c.max_force, above(0.0));
  c.max_torque = given->number("max_torque", c.max_torque, above(0.0));
  c.max_stiffness = given->number("max_stiffness", c.max_stiffness, above(0.0));
  c.workspace_min = given->vector3("workspace_min", c.workspace_min);
  c.workspace_max = given->vector3("workspace_max", c.workspace_max);
  if (!(c.workspace_min.array() < c.workspace_max.array()).all()) {
    const std::string_view key = given->has("workspace_max") ? "workspace_max" : "workspace_min";
    given->fail(key,
                "expected workspace_min < workspace_max in every coordinate, got [" +
                    format_number(c.workspace_min.x()) + ", " + format_number(c.workspace_min.y()) +
                    ", " + format_number(c.workspace_min.z()) + "] and [" +
                    format_number(c.workspace_max.x()) + ", " + format_number(c.workspace_max.y()) +
                    ", " + format_number(c.workspace_max.z()) + "]");
  }
  c.workspace_radius = given->number("workspace_radius", c.workspace_radius, above(0.0));
}

haptic::WorkspaceMapping read_mapping(const ObjectReader& device) {
  haptic::WorkspaceMapping result;
  const auto mapping = device.object("mapping", {"scale", "offset", "force_scale", "torque_scale"});
  if (!mapping) return result;
  result.scale = mapping->number("scale", result.scale, above(0.0));
  if (mapping->has("offset"))
    result.offset = read_pose(mapping->value("offset"), mapping->at("offset"));
  result.force_scale = mapping->number("force_scale", result.force_scale, above(0.0));
  result.torque_scale = mapping->number("torque_scale", result.torque_scale, above(0.0));
  return result;
}

haptic::SafetyOptions read_safety(const ObjectReader& device) {
  haptic::SafetyOptions result;
  const auto safety =
      device.object("safety", {"max_force", "max_torque", "deadline_tolerance", "ramp_cycles",
                               "index_button", "index_orientation", "zero_output_while_indexing"});
  if (!safety) return result;
  result.max_force = safety->number("max_force", result.max_force, at_least(0.0));
  result.max_torque = safety->number("max_torque", result.max_torque, at_least(0.0));
  result.deadline_tolerance =
      safety->number("deadline_tolerance", result.deadline_tolerance, at_least(0.0));
  result.ramp_cycles = safety->integer("ramp_cycles", result.ramp_cycles, at_least(0));
  result.index_button = safety->integer("index_button", result.index_button, closed(-1, 31));
  result.index_orientation = safety->boolean("index_orientation", result.index_orientation);
  result.zero_output_while_indexing =
      safety->boolean("zero_output_while_indexing", result.zero_output_while_indexing);
  return result;
}

}  // namespace

DeviceDescription read_device(const Json* value, const Location& at, const ReadContext& context) {
  DeviceDescription result;
  result.capabilities = haptic::NullDevice::default_capabilities();
  result.capabilities.nominal_rate = context.rate_hz;
  if (value == nullptr) return result;
  const ObjectReader device(
      *value, at,
      {"type", "pose", "file", "playback", "keyframes", "dynamics", "hand", "substeps",
       "start_at_target", "initial_pose", "name", "capabilities", "mapping", "safety"},
      {{"trajectory", "file"}, {"path", "file"}, {"script", "keyframes"}});
  result.type = device.choice("type", result.type, device_types);
  const std::string type = in_quotes(name_of(result.type, device_types));
  if (result.type != DeviceType::null) {
    device.refuse({"pose"}, "type \"null\" (type is " + type + ")");
  }
  if (result.type != DeviceType::trajectory) {
    device.refuse({"file", "playback"}, "type \"trajectory\" (type is " + type + ")");
  }
  if (result.type != DeviceType::simulated_operator) {
    device.refuse({"keyframes", "dynamics", "hand", "substeps", "start_at_target", "initial_pose"},
                  "type \"operator\" (type is " + type + ")");
  }
  if (result.type != DeviceType::hardware) {
    device.refuse({"name"}, "type \"hardware\" (type is " + type + ")");
  }
  switch (result.type) {
    case DeviceType::null:
      if (device.has("pose")) result.null_pose = read_pose(device.value("pose"), device.at("pose"));
      break;
    case DeviceType::trajectory:
      result.capabilities = haptic::TrajectoryDevice::default_capabilities();
      result.trajectory_file = device.required_string("file", "the trajectory CSV file");
      result.trajectory_path = resolve_file(result.trajectory_file, device.at("file"), context,
                                            "trajectory file", /*allow_cgal=*/false);
      result.trajectory.playback = device.choice("playback", result.trajectory.playback, playbacks);
      break;
    case DeviceType::simulated_operator:
      result.capabilities = haptic::SimulatedOperatorOptions::phantom_premium_like();
      result.keyframes = read_keyframes(device);
      read_operator(device, result.simulated_operator);
      break;
    case DeviceType::hardware:
      result.hardware_name = device.required_string("name", "the device backend, e.g. \"dhd\"");
      device.refuse({"capabilities"},
                    "the null, trajectory and operator devices (a hardware device reports its "
                    "own)");
      break;
  }
  result.capabilities.nominal_rate = context.rate_hz;
  read_capabilities(device, result.capabilities);
  if (result.type == DeviceType::simulated_operator) {
    result.simulated_operator.capabilities = result.capabilities;
    try {
      result.simulated_operator.validate();
    } catch (const reduced::Error& error) {
      at.fail(std::string("the simulated operator cannot run at loop.rate_hz = ") +
              format_number(context.rate_hz) + " Hz: " + error.what());
    }
  }
  result.mapping = read_mapping(device);
  result.safety = read_safety(device);
  return result;
}

}  // namespace khz::scene::detail
