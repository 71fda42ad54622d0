#pragma once
// Where a run left the scene's free objects ("dynamics"): what `khz run` prints after its
// summary.

#include <khz/scene/scene_runtime.hpp>

#include <Eigen/Core>

#include <iosfwd>
#include <string>
#include <vector>

namespace khz::run {

/// One free object now, against where it started.
struct FreeBodyState {
  std::string name;                                  ///< The scene's object name.
  Eigen::Vector3d start = Eigen::Vector3d::Zero();   ///< Its centre of mass at the start (m).
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();  ///< Its centre of mass now (m, world).
  double speed = 0.0;                                ///< Of its centre now (m/s).
  bool asleep = false;                               ///< At rest (haptic::World::asleep()).
  int hand = -1;                                     ///< The hand grasping it, or −1.
};

/// Every free object of the runtime's scene, in the scene's order (none: empty).
std::vector<FreeBodyState> free_body_states(const scene::SceneRuntime& runtime);

/// One line per free object: how far it moved, where to, and whether it rests, moves or is
/// grasped. Nothing for none.
void print_free_bodies(std::ostream& out, const std::vector<FreeBodyState>& states);

}  // namespace khz::run
