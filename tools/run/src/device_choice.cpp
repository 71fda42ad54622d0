#include <khz/haptic/device/trajectory_device.hpp>
#include <khz/reduced/errors.hpp>
#include <khz/run/device_choice.hpp>
#include <khz/scene/read_scene.hpp>

namespace khz::run {

std::vector<scene::DeviceDescription> choose_devices(const scene::SceneDescription& scene,
                                                     const DeviceChoice& choice) {
  std::vector<scene::DeviceDescription> devices;
  for (const scene::HapticDescription& hand : scene.haptic) devices.push_back(hand.device);
  if (choice.empty()) return devices;
  const int replacements = static_cast<int>(!choice.trajectory.empty()) +
                           static_cast<int>(!choice.operator_script.empty()) +
                           static_cast<int>(!choice.hardware.empty());
  if (replacements > 1) {
    throw reduced::Error("choose at most one of a trajectory, an operator script and a device");
  }
  if (devices.size() > 1) {
    throw reduced::Error("this scene has " + std::to_string(devices.size()) +
                         " hands, each with its device in the scene file (haptic[i].device); "
                         "--trajectory, --operator and --device replace the device of a scene "
                         "with one hand");
  }
  scene::DeviceDescription& device = devices.front();
  if (!choice.operator_script.empty()) {
    device = scene::read_device_file(choice.operator_script, scene.loop.rate_hz);
    return devices;
  }
  if (!choice.trajectory.empty()) {
    if (device.type != scene::DeviceType::trajectory) {
      device.capabilities = haptic::TrajectoryDevice::default_capabilities();
      device.capabilities.nominal_rate = scene.loop.rate_hz;
      device.trajectory = {};
    }
    device.type = scene::DeviceType::trajectory;
    device.trajectory_file = choice.trajectory.string();
    device.trajectory_path = std::filesystem::absolute(choice.trajectory);
  }
  if (!choice.hardware.empty()) {
    device.type = scene::DeviceType::hardware;
    device.hardware_name = choice.hardware;
  }
  return devices;
}

}  // namespace khz::run
