#pragma once
// The devices `khz run` runs a scene with: the scene's own, or one named on the command line.

#include <khz/scene/scene_description.hpp>

#include <filesystem>
#include <string>
#include <vector>

namespace khz::run {

/// A device replacing the scene's (for scenes with one hand).
struct DeviceChoice {
  /// `khz run --trajectory FILE`: replay this trajectory CSV (haptic::read_trajectory()) with
  /// the scene device's mapping and safety settings.
  std::filesystem::path trajectory;
  /// `khz run --operator SCRIPT`: a device file (scene::read_device_file(), e.g. an operator's
  /// keyframes) replacing the scene's device entirely.
  std::filesystem::path operator_script;
  /// `khz run --device NAME`: a hardware backend by name. None is built into khz (see
  /// examples/device_adapters/), so naming one fails with a message that says so.
  std::string hardware;

  bool empty() const noexcept {
    return trajectory.empty() && operator_script.empty() && hardware.empty();
  }
};

/// The scene's device descriptions, one per hand, with `choice` applied.
/// @throws reduced::IoError, scene::SceneError (reading the operator script); reduced::Error if
///         more than one replacement is given, or any for a scene with several hands.
std::vector<scene::DeviceDescription> choose_devices(const scene::SceneDescription& scene,
                                                     const DeviceChoice& choice);

}  // namespace khz::run
