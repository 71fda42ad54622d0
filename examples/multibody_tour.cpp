// The multi-body runtime with nothing but installed headers: three bodies and two hands
// (docs/HAPTICS.md, "Several bodies and hands"). A fixed plate with a hole (its distance field)
// and two pegs (their pointshells), each held by a simulated operator's hand that presses it
// onto the plate beside the hole; the World queries both pairs every cycle and each hand feels
// its own peg's contact. Runs one simulated second at 1 kHz and prints both hands' forces.
//
// Units and placement: metres, seconds, newtons. Meshes are in their body frame; Body::pose
// places a body in the world. A hand holds its body at Hand::grasp_in_body (body frame); the
// body's pose then follows the hand's coupling: pose = grasp frame · translation(−grasp_in_body).
#include "peg_and_plate.hpp"

#include <khz/haptic/device/safe_device.hpp>
#include <khz/haptic/device/simulated_operator.hpp>
#include <khz/haptic/world/world.hpp>

#include <cstdio>
#include <memory>

namespace kc = khz::contact;
namespace kh = khz::haptic;

namespace {

/// A simulated operator pressing its peg `depth` (m) down over half a second, then holding it,
/// behind a safety layer whose device origin is the world point `grasp` (the peg's grasp point
/// at the start).
struct PressingHand {
  PressingHand(const Eigen::Vector3d& grasp, double depth)
      : device(kh::keyframe_target({{0.0, {}}, {0.5, pose_at(-depth)}, {1.0, pose_at(-depth)}})),
        safe(device, {}, [&] {
          kh::WorkspaceMapping mapping;
          mapping.offset.position = grasp;
          return mapping;
        }()) {}
  static kh::Pose pose_at(double z) {
    kh::Pose pose;
    pose.position.z() = z;
    return pose;
  }
  kh::SimulatedOperator device;
  kh::SafeDevice safe;
};

}  // namespace

int main() {
  // The plate (z in [−0.02, 0], a 20.8 mm hole at the centre) as a distance field; a 2 cm square
  // peg (z in [0, 0.08]) as a pointshell. Both pegs share one pointshell: bodies borrow theirs.
  const kc::DistanceGrid plate_field = khz::examples::plate_field();
  const kc::PointTree peg_tree = khz::examples::peg_tree();

  std::vector<kh::Body> bodies(3);
  bodies[0].name = "plate";
  bodies[0].field = &plate_field;  // fixed at the identity pose
  for (const int peg : {1, 2}) {
    bodies[peg].name = peg == 1 ? "left peg" : "right peg";
    bodies[peg].pointshell = &peg_tree;
    bodies[peg].pose.translation() = Eigen::Vector3d(peg == 1 ? -0.03 : 0.03, 0.0, 0.002);
  }

  // Each peg held 7 cm up its axis; the left one pressed 4 mm down (2 mm into the plate), the
  // right one 3 mm.
  const Eigen::Vector3d grasp_in_body(0.0, 0.0, 0.07);
  PressingHand left(bodies[1].pose * grasp_in_body, 0.004);
  PressingHand right(bodies[2].pose * grasp_in_body, 0.003);
  std::vector<kh::Hand> hands(2);
  for (const int h : {0, 1}) {
    hands[h].body = h + 1;
    hands[h].grasp_in_body = grasp_in_body;
    hands[h].device = h == 0 ? &left.safe : &right.safe;
    hands[h].coupling.object_radius = 0.08;  // the peg's length: scales the rotation terms
    hands[h].coupling.max_rendered_force = left.device.capabilities().max_force;
  }
  kh::World world(bodies, hands, kc::ContactOptions{});
  std::printf("%zu pairs; t (s), per hand: contact force z (N), rendered force z (N), points\n",
              world.pairs().size());

  left.safe.open();
  right.safe.open();
  const double period = 1e-3;
  for (int i = 0; i < 1000; ++i) {
    const double t = i * period;  // simulated time: the watchdog reads the same clock
    const auto records = world.cycle(t, t + period, [t] { return t; });
    if (i % 100 == 99) {
      std::printf("%.2f  left %6.3f %6.3f %3lld   right %6.3f %6.3f %3lld\n", t,
                  records[0].contact.force.z(), records[0].rendered.force.z(),
                  static_cast<long long>(records[0].contact.statistics.points_in_contact),
                  records[1].contact.force.z(), records[1].rendered.force.z(),
                  static_cast<long long>(records[1].contact.statistics.points_in_contact));
    }
  }
  left.safe.close();
  right.safe.close();
}
