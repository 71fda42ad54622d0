#pragma once
// Reading a scene's "device".

#include "read_common.hpp"

#include <khz/scene/device_description.hpp>

namespace khz::scene::detail {

/// Reads and checks the device; nullptr (no "device" key) is a null device.
/// @throws SceneError at the first problem.
DeviceDescription read_device(const Json* value, const Location& at, const ReadContext& context);

}  // namespace khz::scene::detail
