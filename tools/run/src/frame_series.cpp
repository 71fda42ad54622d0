#include <khz/run/frame_series.hpp>
#include <khz/series/vtp_file.hpp>

namespace khz::run {

FrameSeries::FrameSeries(const scene::SceneRuntime& runtime, const std::filesystem::path& directory)
    : m_collection(directory, "run") {
  const scene::SceneDescription& description = runtime.description();
  for (int i = 0; i < static_cast<int>(description.objects.size()); ++i) {
    m_object_names.push_back(description.objects[static_cast<std::size_t>(i)].name);
    m_triangles.push_back(runtime.surface(i).triangles);
  }
  for (const haptic::WorldPair& pair : runtime.world().pairs()) {
    if (!pair.applies_reduced_forces) continue;  // as capture_frame(): each pair once
    m_point_parts.push_back("points_" + m_object_names[static_cast<std::size_t>(pair.pointshell)]);
  }
}

void FrameSeries::write(const FrameContent& frame) {
  for (std::size_t i = 0; i < frame.surfaces.size(); ++i) {
    m_collection.add(frame.time, m_object_names[i], [&](const std::filesystem::path& file) {
      series::write_surface_vtp(file, frame.surfaces[i], m_triangles[i]);
    });
  }
  for (std::size_t p = 0; p < frame.points.size(); ++p) {
    const PointPicture& picture = frame.points[p];
    series::ByteVector state(static_cast<Eigen::Index>(picture.states.size()));
    for (std::size_t s = 0; s < picture.states.size(); ++s) {
      state(static_cast<Eigen::Index>(s)) = static_cast<std::uint8_t>(picture.states[s]);
    }
    m_collection.add(frame.time, m_point_parts[p], [&](const std::filesystem::path& file) {
      series::write_point_cloud_vtp(file, picture.positions, {{"state", std::move(state)}});
    });
  }
  m_collection.add(frame.time, "force", [&](const std::filesystem::path& file) {
    // One point per hand: its grasp point, carrying its force.
    const auto hands = static_cast<Eigen::Index>(frame.forces.size());
    reduced::VertexMatrix points(hands, 3), forces(hands, 3);
    for (Eigen::Index h = 0; h < hands; ++h) {
      points.row(h) = frame.grasp_points[static_cast<std::size_t>(h)].transpose();
      forces.row(h) = frame.forces[static_cast<std::size_t>(h)].transpose();
    }
    series::write_point_cloud_vtp(file, points, {{"force", forces}});
  });
}

}  // namespace khz::run
