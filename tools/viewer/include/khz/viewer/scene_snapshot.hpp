#pragma once
// What the haptic thread hands the drawing thread after every cycle.

#include <khz/haptic/world/cycle_record.hpp>
#include <khz/scene/scene_runtime.hpp>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <array>
#include <cstdint>
#include <span>
#include <vector>

namespace khz::viewer {

/// One cycle's outcome, fixed in size so that handing it over through a haptic::TripleBuffer
/// copies and never allocates.
struct SceneSnapshot {
  /// The most reduced coordinates a scene's reduced objects may have in all.
  static constexpr int max_coordinates = 512;
  /// The most hands a scene may have in the viewer.
  static constexpr int max_hands = 4;
  /// The most contact pairs (haptic::World::pairs()) a scene may have in the viewer.
  static constexpr int max_pairs = 64;
  /// The most objects a scene may have in the viewer.
  static constexpr int max_objects = 32;
  /// The cycle, per hand (the first SnapshotLayout::hand_count() entries): the held object's
  /// grasp frame (`simulation`), the device's (`manipulandum`), the contact force (N) and the
  /// query's counters.
  std::array<haptic::CycleRecord, max_hands> records{};
  /// Per object (the first SnapshotLayout::object_count() entries), its pose after the cycle
  /// (world ← body): a held object's at the cycle's query, a free one's after its step, a fixed
  /// one's as ever.
  std::array<Eigen::Isometry3d, max_objects> poses{};
  /// Every reduced object's q after the cycle's time step, object after object
  /// (SnapshotLayout says where each starts).
  std::array<double, max_coordinates> coordinates{};
  /// Per pair (the first SnapshotLayout::pair_count() entries, in haptic::World::pairs()'s
  /// order), the deepest tree level its query rendered (ContactStatistics::deepest_level, −1
  /// before the first query): with the poses and q, what the drawing thread needs to classify
  /// that pair's points (SnapshotPoints) without reading the World.
  std::array<int, max_pairs> deepest_levels{};
  /// The most sliding points a snapshot lists, over all pairs: the viewer draws further ones as
  /// in contact.
  static constexpr int max_sliding_points = 4096;
  /// Per pair (as deepest_levels), how many of `sliding_points` are its points; each pair's come
  /// after those of the pairs before it.
  std::array<int, max_pairs> sliding_counts{};
  /// The pointshell indices of the points whose friction slid in the cycle
  /// (run::sliding_points()), pair after pair: for SnapshotPoints to colour them apart from the
  /// stuck ones.
  std::array<std::int32_t, max_sliding_points> sliding_points{};
  /// Pair `pair`'s entries of sliding_points.
  std::span<const std::int32_t> sliding(int pair) const noexcept;
};

/// Where each object's q lies in SceneSnapshot::coordinates, fixed before the loop starts.
class SnapshotLayout {
 public:
  /// @throws reduced::Error if the reduced objects have more than
  ///         SceneSnapshot::max_coordinates coordinates in all, the scene more than
  ///         SceneSnapshot::max_hands hands or SceneSnapshot::max_objects objects, or its World
  ///         more than SceneSnapshot::max_pairs pairs.
  explicit SnapshotLayout(const scene::SceneRuntime& runtime);

  int hand_count() const noexcept { return m_hands; }
  int object_count() const noexcept { return static_cast<int>(m_offsets.size()) - 1; }
  int pair_count() const noexcept { return m_pairs; }
  /// Writes the runtime's last records, every object's pose, every reduced object's current
  /// q, every pair's deepest level and its sliding points into `snapshot`. noexcept and
  /// allocation-free: for the haptic thread, right after the cycle.
  void capture(const scene::SceneRuntime& runtime, SceneSnapshot& snapshot) const noexcept;
  /// Object i's q in `snapshot` (r entries; empty for rigid objects).
  Eigen::Map<const Eigen::VectorXd> coordinates(const SceneSnapshot& snapshot,
                                                int object) const noexcept;

 private:
  std::vector<int> m_offsets;  // per object, then the total: q of object i is [o_i, o_i+1)
  int m_hands = 0;
  int m_pairs = 0;
};

}  // namespace khz::viewer
