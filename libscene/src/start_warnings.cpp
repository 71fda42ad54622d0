#include "product_builders.hpp"

#include <khz/haptic/device/safe_device.hpp>
#include <khz/reduced/errors.hpp>
#include <khz/scene/make_device.hpp>

#include <cmath>
#include <numbers>
#include <sstream>
#include <string>

namespace khz::scene::detail {

std::vector<PrepareWarning> start_warnings(const SceneDescription& scene) {
  std::vector<PrepareWarning> warnings;
  for (std::size_t h = 0; h < scene.haptic.size(); ++h) {
    const HapticDescription& hand = scene.haptic[h];
    if (hand.device.type == DeviceType::hardware) continue;  // starts wherever the user holds it
    haptic::DeviceState start;
    try {
      const std::unique_ptr<haptic::Device> device = make_device(hand.device);
      haptic::SafeDevice safe(*device, hand.device.safety, hand.device.mapping);
      safe.open();
      const bool read = safe.read(start);
      safe.close();
      if (!read) continue;
    } catch (const reduced::Error&) {
      continue;  // a device that cannot be made is reported when the scene runs
    }
    const ObjectDescription& object = scene.held_object(static_cast<int>(h));
    const double degrees =
        start.pose.orientation.angularDistance(object.pose.orientation) * 180.0 / std::numbers::pi;
    if (!(degrees > max_start_turn_degrees)) continue;
    std::ostringstream text;
    text.precision(3);
    text << "haptic entry " << h << "'s device starts turned " << degrees
         << " degrees from it (its first reading, through \"mapping\"), so the coupling turns it "
            "that far at the start, through whatever is in the way; give the device's "
            "\"mapping\": {\"offset\": {\"rotation\": ...}} the object's rotation, or start the "
            "device turned as the object is";
    warnings.push_back({object.name, text.str()});
  }
  return warnings;
}

}  // namespace khz::scene::detail
