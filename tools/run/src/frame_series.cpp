#include <khz/run/frame_series.hpp>
#include <khz/series/vtp_file.hpp>

namespace khz::run {

FrameSeries::FrameSeries(const SceneRuntime& runtime, const std::filesystem::path& directory)
    : m_collection(directory, "run") {
  const scene::SceneDescription& description = runtime.description();
  for (int i = 0; i < static_cast<int>(description.objects.size()); ++i) {
    m_object_names.push_back(description.objects[static_cast<std::size_t>(i)].name);
    m_triangles.push_back(runtime.surface(i).triangles);
  }
  const SceneContact& contact = runtime.contact();
  for (int p = 0; p < contact.pair_count(); ++p) {
    m_point_parts.push_back(
        "points_" + m_object_names[static_cast<std::size_t>(contact.pair_objects(p).first)]);
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
    const reduced::VertexMatrix point = frame.grasp_point.transpose();
    const reduced::VertexMatrix force = frame.force.transpose();
    series::write_point_cloud_vtp(file, point, {{"force", force}});
  });
}

}  // namespace khz::run
