#pragma once
// What the haptic thread hands the drawing thread after every cycle.

#include <khz/haptic/cycle/haptic_cycle.hpp>
#include <khz/scene/scene_runtime.hpp>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <array>
#include <vector>

namespace khz::viewer {

/// One cycle's outcome, fixed in size so that handing it over through a haptic::TripleBuffer
/// copies and never allocates.
struct SceneSnapshot {
  /// The most reduced coordinates a scene's reduced objects may have in all.
  static constexpr int max_coordinates = 512;
  /// The most hands a scene may have in the viewer.
  static constexpr int max_hands = 4;
  /// The cycle, per hand (the first SnapshotLayout::hand_count() entries): the held object's
  /// grasp frame (`simulation`), the device's (`manipulandum`), the contact force (N) and the
  /// query's counters.
  std::array<haptic::CycleRecord, max_hands> records{};
  /// Per hand, its held object's pose at the cycle's query (world ← body).
  std::array<Eigen::Isometry3d, max_hands> held_poses{};
  /// Every reduced object's q after the cycle's time step, object after object
  /// (SnapshotLayout says where each starts).
  std::array<double, max_coordinates> coordinates{};
};

/// Where each object's q lies in SceneSnapshot::coordinates, fixed before the loop starts.
class SnapshotLayout {
 public:
  /// @throws reduced::Error if the reduced objects have more than
  ///         SceneSnapshot::max_coordinates coordinates in all, or the scene more than
  ///         SceneSnapshot::max_hands hands.
  explicit SnapshotLayout(const scene::SceneRuntime& runtime);

  int hand_count() const noexcept { return m_hands; }
  /// Writes the runtime's last records, its held objects' poses and every reduced object's
  /// current q into `snapshot`. noexcept and allocation-free: for the haptic thread, right after
  /// the cycle.
  void capture(const scene::SceneRuntime& runtime, SceneSnapshot& snapshot) const noexcept;
  /// Object i's q in `snapshot` (r entries; empty for rigid objects).
  Eigen::Map<const Eigen::VectorXd> coordinates(const SceneSnapshot& snapshot,
                                                int object) const noexcept;

 private:
  std::vector<int> m_offsets;  // per object, then the total: q of object i is [o_i, o_i+1)
  int m_hands = 0;
};

}  // namespace khz::viewer
