#pragma once
// Speed against error of the contact query on a recorded run: the same states queried at every
// fixed level of detail and under time budgets, each compared with the full traversal (thesis
// §3.5.1, §3.10.3, Table 3.1).

#include <khz/reduced/progress.hpp>
#include <khz/scene/export.hpp>
#include <khz/scene/run_summary.hpp>
#include <khz/scene/scene_runtime.hpp>

#include <string>
#include <vector>

namespace khz::scene {

/// Where everything was in one cycle: each hand's grasp frame (its held object's simulation
/// pose), every reduced object's q (empty for rigid objects) and every free object's pose
/// (world ← body, in the scene's order of the free objects).
struct KHZ_SCENE_API RecordedState {
  std::vector<haptic::Pose> grasps;
  std::vector<Eigen::VectorXd> coordinates;
  std::vector<Eigen::Isometry3d> free_poses;
};

/// The state of `runtime` now (for RunOptions::on_frame with frame_every = 1).
KHZ_SCENE_API RecordedState record_state(const SceneRuntime& runtime);

/// One way of querying contact: a name for tables and legends and the options.
struct KHZ_SCENE_API SweepSetting {
  std::string name;
  contact::ContactOptions options;
};

/// The largest level count of the scene's pointshell trees (rigid or deformable); 1 if none.
KHZ_SCENE_API int tree_levels(const PreparedScene& prepared) noexcept;

/// The settings `khz report` compares, all derived from the scene's contact options with
/// temporal coherence off (it changes cost, never the result): first the reference, every
/// level and no degradation; then each fixed level 0 … levels − 2; then time budgets of 50,
/// 100 and 250 µs (with the scene's cold fraction and contact weight).
/// @param levels the pointshell trees' level count (the largest over the scene's pointshells).
KHZ_SCENE_API std::vector<SweepSetting> default_sweep(const contact::ContactOptions& scene_options,
                                                      int levels);

/// How one setting did over the replayed states.
struct KHZ_SCENE_API SweepResult {
  std::string name;
  Spread query_us;          ///< Query cost over the states in contact (µs).
  double mean_nodes = 0.0;  ///< Nodes traversed per query, states in contact.
  /// RMS |F − F_ref| / RMS |F_ref| over the states in contact (every hand's force).
  double force_error = 0.0;
  double torque_error = 0.0;     ///< The same for the torque.
  double max_force_error = 0.0;  ///< max |F − F_ref| / max |F_ref|.
  /// The states replayed: those in contact under the reference, thinned to max_states.
  std::size_t states = 0;
};

/// How many states sweep_contact() replays at most, by default (`khz report`).
inline constexpr std::size_t default_sweep_states = 2000;

/// Replays `states` (those where the reference finds contact for some hand or free object; at
/// most `max_states` of them, evenly spaced) through `runtime`'s World (free objects placed
/// where they were, haptic::World::place_free_body(), then haptic::World::probe(): every pair
/// queried, nothing stepped) under each setting in turn, the first setting being the reference,
/// and restores the scene's options afterwards. The errors cover every hand's wrench and every
/// free object's (haptic::World::body_wrench()). Grasps are let go first (the replay cannot
/// tell what was grasped when): a peg carried in the run is replayed as touched by its gripper.
/// Each setting starts from a reset workspace and sees the states in order, so time budgets warm up
/// as in a run. `progress` hears of stage "finding the states in contact" (one unit a recorded
/// state) and then of one stage a setting, named after it (one unit a replayed state).
/// @throws reduced::Error if `settings` is empty, or as SceneRuntime::set_coordinates();
///         reduced::Cancelled if `progress` returns false (the scene's options restored).
KHZ_SCENE_API std::vector<SweepResult> sweep_contact(
    SceneRuntime& runtime, const std::vector<RecordedState>& states,
    const std::vector<SweepSetting>& settings, std::size_t max_states = default_sweep_states,
    const reduced::ProgressCallback& progress = {});

}  // namespace khz::scene
