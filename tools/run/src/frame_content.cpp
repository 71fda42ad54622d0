#include <khz/run/frame_content.hpp>

namespace khz::run {

FrameContent capture_frame(SceneRuntime& runtime) {
  FrameContent frame;
  const haptic::CycleRecord& record = runtime.cycle().record();
  frame.time = record.time;
  frame.grasp_point = record.simulation.position;
  frame.force = record.contact.force;
  for (int i = 0; i < static_cast<int>(runtime.description().objects.size()); ++i) {
    reduced::VertexMatrix vertices = runtime.deformed_vertices(i);
    const Eigen::Isometry3d& pose = runtime.pose(i);
    for (Eigen::Index v = 0; v < vertices.rows(); ++v) {
      vertices.row(v) = (pose * Eigen::Vector3d(vertices.row(v))).transpose();
    }
    frame.surfaces.push_back(std::move(vertices));
  }
  const SceneContact& contact = runtime.contact();
  for (int p = 0; p < contact.pair_count(); ++p) {
    const auto [pointshell, field] = contact.pair_objects(p);
    frame.points.push_back(classify_points(contact.bodies()[static_cast<std::size_t>(pointshell)],
                                           contact.bodies()[static_cast<std::size_t>(field)],
                                           contact.pair_result(p).statistics.deepest_level));
  }
  return frame;
}

}  // namespace khz::run
