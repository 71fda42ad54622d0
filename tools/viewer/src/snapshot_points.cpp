#include <khz/viewer/snapshot_points.hpp>

namespace khz::viewer {

SnapshotPoints::SnapshotPoints(const scene::SceneRuntime& runtime, const SnapshotLayout& layout)
    : m_layout(layout) {
  const haptic::World& world = runtime.world();
  m_bodies.assign(world.bodies().begin(), world.bodies().end());
  m_field_states.resize(m_bodies.size());
  for (std::size_t i = 0; i < m_bodies.size(); ++i) {
    haptic::Body& body = m_bodies[i];
    body.integrator = nullptr;  // q comes from the snapshot
    const contact::DeformedDistanceField* deformed =
        runtime.prepared().objects[i].deformed_field.get();
    if (deformed != nullptr) {
      m_field_states[i] = std::make_unique<contact::DeformedFieldState>(*deformed);
      body.field = m_field_states[i].get();
    }
  }
  for (int p = 0; p < static_cast<int>(world.pairs().size()); ++p) {
    const haptic::WorldPair& pair = world.pairs()[static_cast<std::size_t>(p)];
    if (pair.applies_reduced_forces) m_pairs.push_back({p, pair.pointshell, pair.field});
  }
  m_pictures.resize(m_pairs.size());
}

SnapshotPoints::~SnapshotPoints() = default;

const std::vector<run::PointPicture>& SnapshotPoints::classify(const SceneSnapshot& snapshot) {
  for (std::size_t i = 0; i < m_bodies.size(); ++i) {
    m_bodies[i].pose = snapshot.poses[i];
    if (m_field_states[i] != nullptr) {
      // Refused only if the haptic thread's own update() refused the same q; keep the last.
      m_field_states[i]->update(m_layout.coordinates(snapshot, static_cast<int>(i)));
    }
  }
  for (std::size_t k = 0; k < m_pairs.size(); ++k) {
    const Pair& pair = m_pairs[k];
    m_pictures[k] =
        run::classify_points(m_bodies[static_cast<std::size_t>(pair.pointshell)],
                             m_layout.coordinates(snapshot, pair.pointshell),
                             m_bodies[static_cast<std::size_t>(pair.field)],
                             snapshot.deepest_levels[static_cast<std::size_t>(pair.world_index)]);
    run::mark_sliding(m_pictures[k], snapshot.sliding(pair.world_index));
  }
  return m_pictures;
}

}  // namespace khz::viewer
