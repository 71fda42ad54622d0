#include "read_device.hpp"

#include "names.hpp"
#include "option_tables.hpp"

#include <khz/haptic/device/null_device.hpp>

#include <cstdint>
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
    const ObjectReader keyframe(value[i], at.element(i),
                                {"time", "position", "rotation", "buttons"},
                                {{"t", "time"}, {"button", "buttons"}});
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
    frame.buttons = keyframe.integer<std::uint32_t>(
        "buttons", 0u, with_text(closed(0, 4294967295.0), "a bitmask in [0, 2^32)"));
    result.push_back(frame);
  }
  return result;
}

void read_capabilities(const ObjectReader& device, haptic::DeviceCapabilities& capabilities) {
  const auto given =
      device.object("capabilities", option_table<haptic::DeviceCapabilities>().keys(),
                    {{"nominal_rate", "loop.rate_hz"}});
  if (!given) return;
  haptic::DeviceCapabilities& c = capabilities;
  read_options(*given, c);
  if (!(c.workspace_min.array() < c.workspace_max.array()).all()) {
    const std::string_view key = given->has("workspace_max") ? "workspace_max" : "workspace_min";
    given->fail(key,
                "expected workspace_min < workspace_max in every coordinate, got [" +
                    format_number(c.workspace_min.x()) + ", " + format_number(c.workspace_min.y()) +
                    ", " + format_number(c.workspace_min.z()) + "] and [" +
                    format_number(c.workspace_max.x()) + ", " + format_number(c.workspace_max.y()) +
                    ", " + format_number(c.workspace_max.z()) + "]");
  }
}

}  // namespace

DeviceDescription read_device(const Json* value, const Location& at, const ReadContext& context) {
  DeviceDescription result;
  result.capabilities = haptic::NullDevice::default_capabilities();
  result.capabilities.nominal_rate = context.rate_hz;
  if (value == nullptr) return result;
  const auto& trajectory_settings = option_table<haptic::TrajectoryDeviceOptions>();
  const auto& operator_settings = option_table<haptic::SimulatedOperatorOptions>();
  const ObjectReader device(*value, at,
                            KeyList("type", "pose", "file", trajectory_settings, "keyframes",
                                    operator_settings, "name", "capabilities", "mapping", "safety"),
                            {{"trajectory", "file"}, {"path", "file"}, {"script", "keyframes"}});
  result.type = device.choice("type", result.type, device_types);
  const std::string type = in_quotes(name_of(result.type, device_types));
  if (result.type != DeviceType::null) {
    device.refuse({"pose"}, "type \"null\" (type is " + type + ")");
  }
  if (result.type != DeviceType::trajectory) {
    device.refuse(KeyList("file", trajectory_settings),
                  "type \"trajectory\" (type is " + type + ")");
  }
  if (result.type != DeviceType::simulated_operator) {
    device.refuse(KeyList("keyframes", operator_settings),
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
      trajectory_settings.read(device, result.trajectory);
      break;
    case DeviceType::simulated_operator:
      result.capabilities = haptic::SimulatedOperatorOptions::phantom_premium_like();
      result.keyframes = read_keyframes(device);
      operator_settings.read(device, result.simulated_operator);
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
  read_block(device, "mapping", result.mapping);
  read_block(device, "safety", result.safety);
  return result;
}

}  // namespace khz::scene::detail
