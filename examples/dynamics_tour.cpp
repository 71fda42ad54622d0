// Dynamic bodies with nothing but installed headers (issue 20): a peg dropped beside the hole of
// a fixed plate lands and goes to sleep; a hand lowers a gripper (a sphere's distance field) onto
// its top, presses its grasp button, carries the peg over the hole and lets go: the peg falls
// through the hole onto the floor below. Runs four simulated seconds at 1 kHz and prints where
// the peg is, whether it sleeps, and the force the hand's body feels.
//
// Units: metres, seconds, newtons, kilograms. A dynamic body's mass and inertia come from its
// closed mesh and a density (reduced::mass_properties()); gravity and the rest are
// haptic::DynamicsOptions.
#include "peg_and_plate.hpp"

#include <khz/contact/field/implicit_shapes.hpp>
#include <khz/haptic/device/null_device.hpp>
#include <khz/haptic/device/safe_device.hpp>
#include <khz/haptic/world/world.hpp>
#include <khz/reduced/mesh/mass_properties.hpp>

#include <cstdio>

namespace kc = khz::contact;
namespace kh = khz::haptic;

int main() {
  // The plate (z in [−0.02, 0], a 20.8 mm hole at the centre) and a floor 10 cm below it, fixed;
  // the 2 cm aluminium peg (z in [0, 0.08] in its frame), dynamic, starting 5 mm above the plate
  // 3 cm beside the hole; the gripper, a 1 cm ball held by the hand, above the peg.
  const kc::DistanceGrid plate_field = khz::examples::plate_field();
  const kc::PointTree peg_tree = khz::examples::peg_tree();
  const kc::ImplicitShape floor = kc::HalfSpace(Eigen::Vector3d::UnitZ(), -0.1);
  const kc::ImplicitShape gripper = kc::Sphere(Eigen::Vector3d::Zero(), 0.01);
  const khz::reduced::MassProperties peg =
      khz::reduced::mass_properties(khz::scene::procedural_shape("peg"), 2700.0);

  std::vector<kh::Body> bodies(4);
  bodies[0].name = "plate";
  bodies[0].field = &plate_field;
  bodies[1].name = "floor";
  bodies[1].field = &floor;
  bodies[2].name = "peg";
  bodies[2].pointshell = &peg_tree;
  bodies[2].pose.translation() = Eigen::Vector3d(0.03, 0.0, 0.005);
  kh::BodyDynamics& dynamics = bodies[2].dynamics.emplace();
  dynamics.inertia.mass = peg.mass;
  dynamics.inertia.centre = peg.centre;
  dynamics.inertia.inertia = peg.inertia;
  bodies[3].name = "gripper";
  bodies[3].field = &gripper;
  const Eigen::Vector3d above_peg(0.03, 0.0, 0.105);
  bodies[3].pose.translation() = above_peg;

  // The hand: a device whose pose the program sets (a real device's comes from the user's
  // hand), button 0 grasping.
  // The device's workspace is a 20 cm cube about its origin, mapped 10 cm above the world's.
  kh::NullDevice device;
  kh::WorkspaceMapping mapping;
  mapping.offset.position = Eigen::Vector3d(0.0, 0.0, 0.1);
  kh::SafeDevice safe(device, {}, mapping);
  kh::Hand hand;
  hand.body = 3;
  hand.device = &safe;
  hand.grasp_button = 0;
  hand.coupling.max_rendered_force = 20.0;
  const auto move_to = [&](const Eigen::Vector3d& position) {
    kh::Pose pose;
    pose.position = position - mapping.offset.position;
    device.set_pose(pose);
  };
  move_to(above_peg);
  kh::World world(bodies, {hand}, kc::ContactOptions{});
  // Friction between the peg and everything it rests on or is held by (μ_s 0.5, μ_k 0.4).
  for (const int other : {0, 1, 3}) world.set_pair_friction(2, other, {0.5, 0.4, 1e-4});
  std::printf("peg: %.1f g; t (s), peg centre x, z (mm), asleep, hand's force z (N), grasped\n",
              peg.mass * 1e3);

  safe.open();
  const double period = 1e-3;
  for (int i = 0; i < 4000; ++i) {
    const double t = i * period;
    if (i == 800) move_to(above_peg - Eigen::Vector3d(0, 0, 0.016));  // onto the peg's top
    if (i == 1200) device.set_buttons(1u);                            // grasp
    if (i == 1300) move_to(above_peg + Eigen::Vector3d(0, 0, 0.03));  // lift
    if (i == 1800) move_to(Eigen::Vector3d(0.0, 0.0, 0.135));         // over the hole
    if (i == 2500) device.set_buttons(0u);                            // let go
    world.cycle(t, t + period, [t] { return t; });
    if (i % 250 == 249) {
      const Eigen::Vector3d centre = world.motion(2)->centre() * 1e3;
      std::printf("%.2f  %6.2f %7.2f  %d  %6.3f  %s\n", t + period, centre.x(), centre.z(),
                  world.asleep(2) ? 1 : 0, world.wrench(0).force.z(),
                  world.hand_of(2) == 0 ? "yes" : "no");
    }
  }
  safe.close();
}
