// One held object against one fixed object, in real time (docs/HAPTICS.md, "One cycle"): a
// simulated operator's hand holds a plate with a hole (its distance field: the haptic object, as
// in the thesis) and presses it onto a fixed peg standing below (its pointshell). A World of these
// two bodies and one hand runs on a HapticLoop thread at 1 kHz for half a second; the records go
// to this thread through a TripleBuffer. Installed headers only (Kilohertz::scene for the
// procedural meshes).
//
// Units and placement: metres, seconds, newtons. `grasp_in_body` is where the hand holds the
// plate, in the plate's body frame; the plate's body pose is the grasp frame moved by −grasp.
// The peg's Body::pose places it (world ← body).
#include "peg_and_plate.hpp"

#include <khz/haptic/device/simulated_operator.hpp>
#include <khz/haptic/loop/haptic_loop.hpp>
#include <khz/haptic/loop/triple_buffer.hpp>
#include <khz/haptic/world/world.hpp>

#include <chrono>
#include <cstdio>
#include <thread>
#include <utility>
#include <vector>

namespace kc = khz::contact;
namespace kh = khz::haptic;

int main() {
  // The held plate (z in [−0.02, 0], body frame) and the fixed peg (z in [0, 0.08]): any field
  // and pointshell (docs/CONTACT.md builds them from your meshes).
  const kc::DistanceGrid held_field = khz::examples::plate_field();
  const kc::PointTree environment_tree = khz::examples::peg_tree();
  // The plate is held at its top face's centre, starting 1 mm above the peg, which stands 3 cm
  // off the hole's axis, its top at z = 0.08.
  const Eigen::Vector3d grasp_in_body = Eigen::Vector3d::Zero();
  kh::Pose start_pose;
  start_pose.position = Eigen::Vector3d(0.0, 0.0, 0.101);
  std::vector<kh::Body> bodies(2);
  bodies[0].name = "plate";
  bodies[0].field = &held_field;
  bodies[0].pose = kh::held_body_pose(start_pose, grasp_in_body);
  bodies[1].name = "peg";
  bodies[1].pointshell = &environment_tree;
  bodies[1].pose.translation() = Eigen::Vector3d(0.03, 0.0, 0.0);

  // The operator lowers the hand 4 mm in 0.3 s (3 mm into the peg), device frame = world frame
  // moved to the start pose.
  kh::Pose pressed;
  pressed.position.z() = -0.004;
  kh::SimulatedOperator device(kh::keyframe_target({{0.0, {}}, {0.3, pressed}, {0.5, pressed}}));
  kh::WorkspaceMapping mapping;
  mapping.offset.position = start_pose.position;
  kh::SafeDevice safe(device, {}, mapping);  // clamps, watchdog, indexing
  safe.open();

  kh::Hand hand;  // holds body 0 at grasp_in_body through the safety layer
  hand.grasp_in_body = grasp_in_body;
  hand.device = &safe;
  hand.coupling.object_radius = 0.05;  // the held object's size (m), see below
  hand.coupling.max_rendered_force = device.capabilities().max_force;
  const kc::ContactOptions contact_options;                     // k_C = 1000 N/m, L = 10
  kh::World world(std::move(bodies), {hand}, contact_options);  // workspaces allocated here

  kh::TripleBuffer<kh::CycleRecord> records;  // haptic thread → this one, never blocking
  const auto start = std::chrono::steady_clock::now();
  const auto seconds = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  };
  kh::HapticLoop loop({.rate_hz = 1000.0, .realtime_priority = true, .cpu = 0});
  loop.start([&](const kh::CycleClock& c) {
    const double now = seconds();
    // One record per hand; the watchdog reads the same clock.
    records.back() = world.cycle(now, now + c.period, seconds)[0];
    records.publish();
  });
  for (int i = 0; i < 5; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    records.update();
    const kh::CycleRecord& last = records.front();
    std::printf("t = %.2f s: contact force z %6.3f N, rendered %6.3f N, %lld points\n", last.time,
                last.contact.force.z(), last.rendered.force.z(),
                static_cast<long long>(last.contact.statistics.points_in_contact));
  }
  loop.stop();
  safe.close();
  const kh::LoopStatistics statistics = loop.statistics();
  std::printf("%lld cycles, work %.1f µs mean, %.1f µs p99, %lld deadline misses\n",
              static_cast<long long>(statistics.cycles), statistics.mean_work, statistics.p99_work,
              static_cast<long long>(statistics.deadline_misses));
  for (const std::string& warning : loop.warnings()) std::printf("loop: %s\n", warning.c_str());
}
