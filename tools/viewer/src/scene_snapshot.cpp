#include <khz/run/point_states.hpp>
#include <khz/viewer/scene_snapshot.hpp>

#include <algorithm>
#include <string>

namespace khz::viewer {

SnapshotLayout::SnapshotLayout(const scene::SceneRuntime& runtime) : m_offsets{0} {
  for (int i = 0; i < static_cast<int>(runtime.description().objects.size()); ++i) {
    const reduced::ReducedIntegrator* integrator = runtime.integrator(i);
    const auto r = integrator != nullptr ? static_cast<int>(integrator->coordinates().size()) : 0;
    m_offsets.push_back(m_offsets.back() + r);
  }
  if (m_offsets.back() > SceneSnapshot::max_coordinates) {
    throw reduced::Error("the viewer draws at most " +
                         std::to_string(SceneSnapshot::max_coordinates) +
                         " reduced coordinates in all; this scene's reduced objects have " +
                         std::to_string(m_offsets.back()));
  }
  if (object_count() > SceneSnapshot::max_objects) {
    throw reduced::Error("the viewer draws at most " + std::to_string(SceneSnapshot::max_objects) +
                         " objects; this scene has " + std::to_string(object_count()));
  }
  m_hands = runtime.hand_count();
  if (m_hands > SceneSnapshot::max_hands) {
    throw reduced::Error("the viewer draws at most " + std::to_string(SceneSnapshot::max_hands) +
                         " hands; this scene has " + std::to_string(m_hands));
  }
  m_pairs = static_cast<int>(runtime.world().pairs().size());
  if (m_pairs > SceneSnapshot::max_pairs) {
    throw reduced::Error("the viewer draws at most " + std::to_string(SceneSnapshot::max_pairs) +
                         " contact pairs; this scene has " + std::to_string(m_pairs));
  }
}

void SnapshotLayout::capture(const scene::SceneRuntime& runtime,
                             SceneSnapshot& snapshot) const noexcept {
  const std::span<const haptic::CycleRecord> records = runtime.world().records();
  for (int h = 0; h < m_hands; ++h) {
    snapshot.records[static_cast<std::size_t>(h)] = records[static_cast<std::size_t>(h)];
  }
  for (int i = 0; i < object_count(); ++i) {
    snapshot.poses[static_cast<std::size_t>(i)] = runtime.pose(i);
  }
  for (std::size_t i = 0; i + 1 < m_offsets.size(); ++i) {
    const reduced::ReducedIntegrator* integrator = runtime.integrator(static_cast<int>(i));
    if (integrator == nullptr) continue;
    const Eigen::VectorXd& q = integrator->coordinates();
    std::copy(q.data(), q.data() + q.size(), snapshot.coordinates.begin() + m_offsets[i]);
  }
  std::size_t listed = 0;
  for (int p = 0; p < m_pairs; ++p) {
    snapshot.deepest_levels[static_cast<std::size_t>(p)] =
        runtime.world().pair_result(p).statistics.deepest_level;
    const std::size_t count =
        run::sliding_points(runtime.world(), p, std::span(snapshot.sliding_points).subspan(listed));
    snapshot.sliding_counts[static_cast<std::size_t>(p)] = static_cast<int>(count);
    listed += count;
  }
}

std::span<const std::int32_t> SceneSnapshot::sliding(int pair) const noexcept {
  std::size_t begin = 0;
  for (int p = 0; p < pair; ++p)
    begin += static_cast<std::size_t>(sliding_counts[static_cast<std::size_t>(p)]);
  return std::span(sliding_points)
      .subspan(begin, static_cast<std::size_t>(sliding_counts[static_cast<std::size_t>(pair)]));
}

Eigen::Map<const Eigen::VectorXd> SnapshotLayout::coordinates(const SceneSnapshot& snapshot,
                                                              int object) const noexcept {
  const auto i = static_cast<std::size_t>(object);
  return {snapshot.coordinates.data() + m_offsets[i], m_offsets[i + 1] - m_offsets[i]};
}

}  // namespace khz::viewer
