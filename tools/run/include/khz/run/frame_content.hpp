#pragma once
// A snapshot of a running scene in world coordinates: what a frame picture and a ParaView time
// step show.

#include <khz/run/point_states.hpp>
#include <khz/scene/scene_runtime.hpp>

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
  /// Per hand: its held object's grasp point (m) and the last contact force on it (N).
  std::vector<Eigen::Vector3d> grasp_points, forces;
};

/// The runtime's scene now (allocates: not for the haptic thread).
FrameContent capture_frame(scene::SceneRuntime& runtime);

}  // namespace khz::run
