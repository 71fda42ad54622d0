#include <khz/viewer/mouse_placement.hpp>

namespace khz::viewer {

haptic::WorkspaceMapping mouse_mapping(const haptic::Pose& grasp_start) noexcept {
  haptic::WorkspaceMapping mapping;
  mapping.offset = grasp_start;
  return mapping;
}

Eigen::Vector3d device_position(const haptic::WorkspaceMapping& mapping,
                                const Eigen::Vector3d& world) noexcept {
  return mapping.offset.orientation.conjugate() * (world - mapping.offset.position) / mapping.scale;
}

}  // namespace khz::viewer
