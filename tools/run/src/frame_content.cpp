#include <khz/run/frame_content.hpp>

#include <cstdint>
#include <span>
#include <utility>
#include <vector>

namespace khz::run {

FrameContent capture_frame(scene::SceneRuntime& runtime) {
  FrameContent frame;
  const haptic::World& world = runtime.world();
  for (const haptic::CycleRecord& record : world.records()) {
    frame.time = record.time;
    frame.grasp_points.push_back(record.simulation.position);
    frame.forces.push_back(record.contact.force);
  }
  for (int i = 0; i < static_cast<int>(runtime.description().objects.size()); ++i) {
    reduced::VertexMatrix vertices = runtime.deformed_vertices(i);
    const Eigen::Isometry3d& pose = runtime.pose(i);
    for (Eigen::Index v = 0; v < vertices.rows(); ++v) {
      vertices.row(v) = (pose * Eigen::Vector3d(vertices.row(v))).transpose();
    }
    frame.surfaces.push_back(std::move(vertices));
  }
  for (int p = 0; p < static_cast<int>(world.pairs().size()); ++p) {
    const haptic::WorldPair& pair = world.pairs()[static_cast<std::size_t>(p)];
    if (!pair.applies_reduced_forces) continue;  // a pair of two held objects, drawn once
    PointPicture picture =
        classify_points(world.bodies()[static_cast<std::size_t>(pair.pointshell)],
                        world.bodies()[static_cast<std::size_t>(pair.field)],
                        world.pair_result(p).statistics.deepest_level);
    std::vector<std::int32_t> sliding(
        static_cast<std::size_t>(world.pair_result(p).statistics.points_sliding));
    mark_sliding(picture, std::span(sliding).first(sliding_points(world, p, sliding)));
    frame.points.push_back(std::move(picture));
  }
  return frame;
}

}  // namespace khz::run
