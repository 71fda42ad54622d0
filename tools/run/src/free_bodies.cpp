#include <khz/run/free_bodies.hpp>

#include <ostream>

namespace khz::run {

std::vector<FreeBodyState> free_body_states(const scene::SceneRuntime& runtime) {
  std::vector<FreeBodyState> states;
  const haptic::World& world = runtime.world();
  const std::vector<scene::ObjectDescription>& objects = runtime.description().objects;
  for (int i = 0; i < static_cast<int>(objects.size()); ++i) {
    const haptic::FreeBodyMotion* motion = world.motion(i);
    if (motion == nullptr) continue;
    const scene::ObjectDescription& object = objects[static_cast<std::size_t>(i)];
    const Eigen::Vector3d& centre_in_body = motion->inertia().centre;
    FreeBodyState state;
    state.name = object.name;
    state.start = object.pose.position + object.pose.orientation * centre_in_body;
    state.centre = motion->centre();
    state.speed = motion->velocity().norm();
    state.asleep = world.asleep(i);
    state.hand = world.hand_of(i);
    states.push_back(state);
  }
  return states;
}

void print_free_bodies(std::ostream& out, const std::vector<FreeBodyState>& states) {
  const Eigen::IOFormat vector(Eigen::StreamPrecision, Eigen::DontAlignCols, ", ", ", ", "", "",
                               "[", "]");
  for (const FreeBodyState& s : states) {
    out << "free body \"" << s.name << "\": moved " << (s.centre - s.start).norm() << " m, to "
        << s.centre.transpose().format(vector) << " m; ";
    if (s.hand >= 0) {
      out << "grasped by hand " << s.hand;
    } else if (s.asleep) {
      out << "at rest";
    } else {
      out << "moving at " << s.speed << " m/s";
    }
    out << "\n";
  }
}

}  // namespace khz::run
