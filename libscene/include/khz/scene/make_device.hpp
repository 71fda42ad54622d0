#pragma once
// The devices a scene file describes, made.

#include <khz/haptic/device/device.hpp>
#include <khz/scene/device_description.hpp>
#include <khz/scene/export.hpp>

#include <memory>

namespace khz::scene {

/// Makes the device a description asks for (not yet opened): a haptic::NullDevice at its pose,
/// a haptic::TrajectoryDevice reading its file, or a haptic::SimulatedOperator following its
/// keyframes, each with the description's capabilities.
/// @throws reduced::Error for a hardware device (no backend is built into the libraries: wrap
///         your SDK in a haptic::Device, as examples/device_adapters/ does, and pass it to
///         SceneRuntime), or as the device's constructor (e.g. an unreadable trajectory).
KHZ_SCENE_API std::unique_ptr<haptic::Device> make_device(const DeviceDescription& device);

/// How long a device made from `device` plays (s): an operator's last keyframe time; a
/// trajectory's length (its sample count times the period for sample_per_read playback, its
/// last minus first sample time otherwise); 0 for null and hardware devices, which play until
/// stopped.
/// @param made the device make_device(device) returned.
KHZ_SCENE_API double device_duration(const DeviceDescription& device, const haptic::Device& made);

}  // namespace khz::scene
