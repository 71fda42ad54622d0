#pragma once
// Which device drives the haptic object, and how its poses and wrenches map to the scene.

#include <khz/haptic/common.hpp>
#include <khz/haptic/device/device.hpp>
#include <khz/haptic/device/safe_device.hpp>
#include <khz/haptic/device/simulated_operator.hpp>
#include <khz/haptic/device/trajectory_device.hpp>

#include <filesystem>
#include <string>
#include <vector>

namespace khz::scene {

/// JSON device.type.
enum class DeviceType {
  null,                ///< "null": haptic::NullDevice at a fixed pose (the default).
  trajectory,          ///< "trajectory": haptic::TrajectoryDevice replaying a CSV file.
  simulated_operator,  ///< "operator": haptic::SimulatedOperator following keyframes.
  hardware,            ///< "hardware": a device backend chosen by name.
};

/// JSON device. Members list their JSON key; settings of another type than `type` keep their
/// defaults (the reader refuses them in the file).
struct DeviceDescription {
  DeviceType type = DeviceType::null;  ///< "type".

  // --- null ---
  /// "pose": the pose NullDevice::set_pose() reports ({"position", "rotation"} as an object's
  /// pose, device frame). Default: identity.
  haptic::Pose null_pose;

  // --- trajectory ---
  /// "file" (required): the trajectory CSV (haptic::read_trajectory()) as written.
  std::string trajectory_file;
  /// `trajectory_file` resolved against the scene file's directory (absolute).
  std::filesystem::path trajectory_path;
  /// "playback": "sample_per_read" (default) | "at_nominal_rate"; TrajectoryDeviceOptions.
  haptic::TrajectoryDeviceOptions trajectory;

  // --- operator ---
  /// "keyframes" (required, ≥ 1): [{"time": s, "position": [x, y, z], "rotation": {"axis",
  /// "degrees"}, "buttons": mask}, ...], times strictly increasing: the hand's target
  /// (keyframe_target()), in device-frame coordinates, and the buttons held from each keyframe
  /// to the next (keyframe_buttons(); default 0), e.g. to grasp with haptic[h].grasp_button.
  std::vector<haptic::Keyframe> keyframes;
  /// The virtual device and hand, haptic::SimulatedOperatorOptions: JSON "dynamics" → device
  /// (mass, inertia, damping, rotational_damping), "hand" (mass, inertia, stiffness, damping,
  /// rotational_stiffness, rotational_damping), "substeps", "start_at_target", "initial_pose"
  /// (a pose), with the library's defaults. Its capabilities are `capabilities` below.
  haptic::SimulatedOperatorOptions simulated_operator;

  // --- hardware ---
  /// "name" (required): the backend, e.g. "openhaptics", "dhd" or "chai3d" (the adapters in
  /// examples/device_adapters/); whether it exists is known only when the scene runs.
  std::string hardware_name;

  // --- null, trajectory, operator ---
  /// "capabilities": overrides of the device's defaults (NullDevice::default_capabilities(),
  /// TrajectoryDevice::default_capabilities(), SimulatedOperatorOptions::
  /// phantom_premium_like()), JSON keys as DeviceCapabilities: input_dof, output_dof, max_force,
  /// max_torque, max_stiffness, workspace_min, workspace_max, workspace_radius. nominal_rate is
  /// not a key: it is the loop's rate_hz. A hardware device reports its own.
  haptic::DeviceCapabilities capabilities;

  // --- every type ---
  /// "mapping": device → scene (thesis §4.5), haptic::WorkspaceMapping: "scale", "offset" (a
  /// pose), "force_scale", "torque_scale". Default: identity.
  haptic::WorkspaceMapping mapping;
  /// "safety": haptic::SafetyOptions, same names: max_force and max_torque (absent: the
  /// device's limits alone), deadline_tolerance, ramp_cycles, index_button (−1: none),
  /// index_orientation, zero_output_while_indexing.
  haptic::SafetyOptions safety;
};

}  // namespace khz::scene
