#pragma once
// The pointshell points each contact pair's query looked at and those in contact (thesis
// Figure 3.1), classified on the drawing thread from a snapshot rather than from the live World.

#include <khz/contact/field/deformed_distance_field.hpp>
#include <khz/haptic/world/body.hpp>
#include <khz/run/point_states.hpp>
#include <khz/scene/scene_runtime.hpp>
#include <khz/viewer/scene_snapshot.hpp>

#include <memory>
#include <vector>

namespace khz::viewer {

/// Classifies each contact pair's points as run::capture_frame() does for the frame pictures
/// (run::classify_points() at the pair's deepest level), from a SceneSnapshot, while the
/// haptic thread keeps running the World.
///
/// What it reads: the point trees and rigid distance fields (immutable once prepared, so the
/// two threads may read them at once); the poses of the objects no hand holds (they never
/// move: copied at construction); and from each snapshot the held objects' poses, the reduced
/// objects' q and each pair's deepest level. It never reads an integrator of the World, and a
/// reduced distance-field object's contact::DeformedFieldState — which the haptic thread
/// update()s every cycle — is replaced by one of its own, update()d to the snapshot's q.
class SnapshotPoints {
 public:
  /// Before the haptic loop starts: copies what it needs of `runtime`'s World.
  /// @param layout where the snapshots keep each object's q; must outlive this.
  SnapshotPoints(const scene::SceneRuntime& runtime, const SnapshotLayout& layout);
  ~SnapshotPoints();
  SnapshotPoints(const SnapshotPoints&) = delete;
  SnapshotPoints& operator=(const SnapshotPoints&) = delete;

  /// How many pictures classify() gives: one per pair of the World, except the second query of
  /// two held objects (the same contact seen from the other hand), as run::capture_frame().
  int picture_count() const noexcept { return static_cast<int>(m_pairs.size()); }

  /// Every drawn pair's points as in `snapshot`: run::classify_points() of its pointshell at
  /// the snapshot's pose and q against its field at the snapshot's pose (and q), down to the
  /// pair's deepest level, its sliding points marked (run::mark_sliding()). A q that a deformed
  /// field refuses (contact::DeformedFieldState::update() returns false, as it did on the
  /// haptic thread) leaves that field at the last q it took. Allocates and costs one distance per
  /// node looked at: not for the haptic thread.
  /// @returns picture_count() pictures, valid until the next call.
  const std::vector<run::PointPicture>& classify(const SceneSnapshot& snapshot);

 private:
  struct Pair {
    int world_index;  // in haptic::World::pairs() and SceneSnapshot::deepest_levels
    int pointshell;   // body (= scene object) indices
    int field;
  };

  const SnapshotLayout& m_layout;
  std::vector<haptic::Body> m_bodies;  // the World's, without integrators, own deformed fields
  std::vector<std::unique_ptr<contact::DeformedFieldState>> m_field_states;  // per body, or null
  std::vector<Pair> m_pairs;
  std::vector<run::PointPicture> m_pictures;
};

}  // namespace khz::viewer
