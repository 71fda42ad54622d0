#include <khz/haptic/device/null_device.hpp>
#include <khz/haptic/device/simulated_operator.hpp>
#include <khz/haptic/device/trajectory_device.hpp>
#include <khz/reduced/errors.hpp>
#include <khz/scene/make_device.hpp>

namespace khz::scene {

std::unique_ptr<haptic::Device> make_device(const DeviceDescription& device) {
  switch (device.type) {
    case DeviceType::null: {
      auto null = std::make_unique<haptic::NullDevice>(device.capabilities);
      null->set_pose(device.null_pose);
      return null;
    }
    case DeviceType::trajectory:
      return std::make_unique<haptic::TrajectoryDevice>(device.trajectory_path, device.trajectory,
                                                        device.capabilities);
    case DeviceType::simulated_operator: {
      haptic::SimulatedOperatorOptions options = device.simulated_operator;
      options.capabilities = device.capabilities;
      return std::make_unique<haptic::SimulatedOperator>(
          haptic::keyframe_target(device.keyframes), options,
          haptic::keyframe_buttons(device.keyframes));
    }
    case DeviceType::hardware:
      break;
  }
  throw reduced::Error("device \"" + device.hardware_name +
                       "\": the Kilohertz libraries have no hardware backends built in; wrap "
                       "your device's SDK in a haptic::Device (see examples/device_adapters/ and "
                       "docs/DEVICES.md) and run the scene with it");
}

double device_duration(const DeviceDescription& device, const haptic::Device& made) {
  if (device.type == DeviceType::simulated_operator) return device.keyframes.back().time;
  if (const auto* trajectory = dynamic_cast<const haptic::TrajectoryDevice*>(&made)) {
    const double period = 1.0 / device.capabilities.nominal_rate;
    return device.trajectory.playback == haptic::Playback::sample_per_read
               ? period * static_cast<double>(trajectory->samples().size())
               : trajectory->samples().back().time - trajectory->samples().front().time;
  }
  return 0.0;
}

}  // namespace khz::scene
