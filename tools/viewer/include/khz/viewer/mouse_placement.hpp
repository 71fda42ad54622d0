#pragma once
// Where the viewer puts the mouse device in a scene: how its positions map into the world.

#include <khz/haptic/common.hpp>
#include <khz/haptic/device/safe_device.hpp>

#include <Eigen/Core>

namespace khz::viewer {

/// The workspace mapping of the mouse device (haptic::SafeDevice's, device → world): the device
/// origin at the held object's grasp point where the scene starts, the device axes turned like
/// the held object there, one device metre one world metre. A 3-DOF device reports the identity
/// orientation, so the coupling then keeps the held object turned as the scene placed it.
/// @param grasp_start the held object's grasp frame at the start (haptic::VirtualCoupling's
///        simulation_pose() before the first cycle); a unit quaternion.
haptic::WorkspaceMapping mouse_mapping(const haptic::Pose& grasp_start) noexcept;

/// The device position (m, device axes) that `mapping` takes to the world point `world` (m): the
/// inverse of x_world = t + R (scale · x_device). `mapping` must be valid
/// (haptic::WorkspaceMapping::validate()).
Eigen::Vector3d device_position(const haptic::WorkspaceMapping& mapping,
                                const Eigen::Vector3d& world) noexcept;

}  // namespace khz::viewer
