#pragma once
// A snapshot of a running scene in world coordinates: what a frame picture and a ParaView time
// step show.

#include <khz/run/point_states.hpp>
#include <khz/run/scene_runtime.hpp>

#include <Eigen/Core>

#include <vector>

namespace khz::run {

/// The scene at one instant, in the world frame (m).
struct FrameContent {
  double time = 0.0;  ///< The last cycle's time (s).
  /// Per object: its surface's vertices deformed to its q and placed at its pose (the
  /// triangles are SceneRuntime::surface(i).triangles).
  std::vector<reduced::VertexMatrix> surfaces;
  /// Per contact pair: its pointshell's points classified at the pair's last deepest level.
  std::vector<PointPicture> points;
  Eigen::Vector3d grasp_point = Eigen::Vector3d::Zero();  ///< The held object's (m).
  Eigen::Vector3d force = Eigen::Vector3d::Zero();        ///< Last contact force on it (N).
};

/// The runtime's scene now (allocates: not for the haptic thread).
FrameContent capture_frame(SceneRuntime& runtime);

}  // namespace khz::run
