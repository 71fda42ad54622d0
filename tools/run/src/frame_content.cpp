#include <khz/run/frame_content.hpp>

#include <utility>

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
    if (world.pair_result(p).statistics.points_sliding > 0) {
      for (std::size_t s = 0; s < picture.states.size(); ++s) {
        if (picture.states[s] == PointState::in_contact &&
            world.friction_state(p, static_cast<Eigen::Index>(s)) ==
                contact::FrictionState::sliding) {
          picture.states[s] = PointState::sliding;
        }
      }
    }
    frame.points.push_back(std::move(picture));
  }
  return frame;
}

}  // namespace khz::run
