// What dynamic bodies cost a World's cycle (issue 20), on the procedural peg and plate of
// examples/dynamics_tour (a 64³ plate field, the peg's 3-level repulsion pointshell):
//   held_peg_on_plate     the reference: the peg held by a hand, resting on the plate
//   dynamic_peg_on_plate  the same peg free and awake (sleeping off), resting there: its query
//                         and its FreeBodyMotion step, no coupling
//   asleep_peg_on_plate   the same peg asleep: not stepped, not queried against the plate (the
//                         held gripper's query of it remains)
//   carry_peg_in_hole     pick and place: a gripper ball holding the grasped peg in the hole,
//                         pressed against a wall, its contacts and weight part of the hand's
//                         wrench
//   pick_and_place_scene  example (h), examples/scenes/pick_and_place.json with its friction,
//                         run through its whole script again and again (prepared through the
//                         default product cache; the runtime is rebuilt between runs, untimed):
//                         every cycle of picking, carrying, inserting and letting go
// Each prints µs per cycle (mean and p99 of the cycles timed one by one) and its ratio to the
// held reference measured in the same run.
#include "peg_and_plate.hpp"

#include <khz/contact/field/implicit_shapes.hpp>
#include <khz/haptic/device/null_device.hpp>
#include <khz/haptic/device/safe_device.hpp>
#include <khz/haptic/world/world.hpp>
#include <khz/reduced/mesh/mass_properties.hpp>
#include <khz/scene/cache_directory.hpp>
#include <khz/scene/prepare_scene.hpp>
#include <khz/scene/read_scene.hpp>
#include <khz/scene/scene_runtime.hpp>

#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <vector>

namespace {

namespace kc = khz::contact;
namespace kh = khz::haptic;

struct Products {
  kc::DistanceGrid plate = khz::examples::plate_field();
  kc::PointTree peg = khz::examples::peg_tree();
  kc::ImplicitShape gripper = kc::Sphere(Eigen::Vector3d::Zero(), 0.01);
  khz::reduced::MassProperties peg_mass =
      khz::reduced::mass_properties(khz::scene::procedural_shape("peg"), 2700.0);
};
const Products& products() {
  static const Products instance;
  return instance;
}

enum class Case { held, dynamic, asleep, carry };

/// The World of one case, its hand on a NullDevice at the held body's grasp point, run until
/// settled (and, for `carry`, the peg grasped and placed half-way into the hole).
struct Rig {
  explicit Rig(Case which) : safe(device) {
    const Products& p = products();
    std::vector<kh::Body> bodies(3);
    bodies[0].name = "plate";
    bodies[0].field = &p.plate;
    bodies[1].name = "peg";
    bodies[1].pointshell = &p.peg;
    bodies[1].pose.translation() = Eigen::Vector3d(0.03, 0.0, 0.0);
    bodies[2].name = "gripper";
    bodies[2].field = &p.gripper;
    bodies[2].pose.translation() = Eigen::Vector3d(0.03, 0.0, 0.2);
    kh::Hand hand;
    hand.device = &safe;
    hand.grasp_button = 0;
    hand.coupling.max_rendered_force = 20.0;
    if (which == Case::held) {
      hand.body = 1;
      hand.grasp_in_body = Eigen::Vector3d(0.0, 0.0, 0.08);
    } else {
      hand.body = 2;
      kh::BodyDynamics& dynamics = bodies[1].dynamics.emplace();
      dynamics.inertia.mass = p.peg_mass.mass;
      dynamics.inertia.centre = p.peg_mass.centre;
      dynamics.inertia.inertia = p.peg_mass.inertia;
    }
    const Eigen::Vector3d start =
        bodies[static_cast<std::size_t>(hand.body)].pose * hand.grasp_in_body;
    // The held peg is pressed 0.2 mm into the plate, about what the dynamic one's weight does.
    set_hand(which == Case::held ? start - Eigen::Vector3d(0, 0, 2e-4) : start);
    world = std::make_unique<kh::World>(bodies, std::vector<kh::Hand>{hand}, kc::ContactOptions{});
    for (const int other : {0, 2}) world->set_pair_friction(1, other, {0.5, 0.4, 1e-4});
    kh::DynamicsOptions options;
    if (which == Case::dynamic) options.sleep_speed = 0.0;  // stays awake
    world->set_dynamics(options);
    safe.open();
    run(1000);
    if (which == Case::carry) {
      // Onto the peg's top, grasp, lift 2 cm, over the hole, down into it and 0.6 mm aside, so
      // that the peg (0.4 mm clear of each wall when centred) presses on a wall.
      set_hand(Eigen::Vector3d(0.03, 0.0, 0.0895));
      run(400);
      device.set_buttons(1u);
      run(1);
      set_hand(Eigen::Vector3d(0.03, 0.0, 0.11));
      run(500);
      set_hand(Eigen::Vector3d(0.0, 0.0, 0.11));
      run(500);
      set_hand(Eigen::Vector3d(6e-4, 0.0, 0.07));
      run(1000);
    }
  }
  void set_hand(const Eigen::Vector3d& position) {
    kh::Pose pose;
    pose.position = position;
    device.set_pose(pose);
  }
  void run(int cycles) {
    for (int i = 0; i < cycles; ++i, ++cycle) {
      const double t = cycle * 1e-3;
      world->cycle(t, t + 1e-3, [t] { return t; });
    }
  }

  kh::NullDevice device;
  kh::SafeDevice safe;
  std::unique_ptr<kh::World> world;
  int cycle = 0;
};

/// Mean µs per cycle of the held reference, measured first (benchmarks run in registration
/// order), for the ratios.
double held_mean_us = 0.0;

double mean_of(const std::vector<double>& times) {
  double sum = 0.0;
  for (const double t : times) sum += t;
  return sum / static_cast<double>(times.size());
}

/// Mean and p99 of `times` (µs, not empty) as counters, with the mean's ratio to the held
/// reference.
void report(benchmark::State& state, std::vector<double> times) {
  const double mean = mean_of(times);
  std::sort(times.begin(), times.end());
  state.counters["mean_us"] = mean;
  state.counters["p99_us"] = times[times.size() * 99 / 100];
  if (held_mean_us > 0.0) state.counters["x_held"] = mean / held_mean_us;
}

void BM_WorldCycle(benchmark::State& state, Case which) {
  Rig rig(which);
  if (which == Case::asleep && !rig.world->asleep(1)) state.SkipWithError("the peg is awake");
  if (which == Case::carry && (rig.world->hand_of(1) != 0 ||
                               rig.world->records()[0].contact.statistics.points_in_contact == 0)) {
    state.SkipWithError("the peg is not grasped, or touches nothing");
  }
  std::vector<double> times;
  times.reserve(1 << 20);
  for (auto _ : state) {
    const auto begin = std::chrono::steady_clock::now();
    rig.run(1);
    times.push_back(
        std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - begin)
            .count());
  }
  if (times.empty()) return;
  if (which == Case::held) held_mean_us = mean_of(times);
  report(state, std::move(times));
  state.counters["points"] =
      static_cast<double>(rig.world->records()[0].contact.statistics.points_in_contact +
                          rig.world->body_wrench(1).statistics.points_in_contact);
}

BENCHMARK_CAPTURE(BM_WorldCycle, held_peg_on_plate, Case::held)->MinTime(1.0);
BENCHMARK_CAPTURE(BM_WorldCycle, dynamic_peg_on_plate, Case::dynamic)->MinTime(1.0);
BENCHMARK_CAPTURE(BM_WorldCycle, asleep_peg_on_plate, Case::asleep)->MinTime(1.0);
BENCHMARK_CAPTURE(BM_WorldCycle, carry_peg_in_hole, Case::carry)->MinTime(1.0);

void BM_PickAndPlaceScene(benchmark::State& state) {
  khz::scene::ProductCache cache(khz::scene::default_cache_directory());
  const khz::scene::PreparedScene prepared = khz::scene::prepare_scene(
      khz::scene::read_scene(KHZ_SCENE_EXAMPLES_DIR "/pick_and_place.json"), cache);
  const double period = 1.0 / prepared.description.loop.rate_hz;
  std::unique_ptr<khz::scene::SceneRuntime> runtime;
  int cycle = 0, cycles = 0;
  std::vector<double> times;
  times.reserve(1 << 20);
  for (auto _ : state) {
    if (cycle == cycles) {  // a fresh run of the script
      state.PauseTiming();
      runtime.reset();
      runtime = std::make_unique<khz::scene::SceneRuntime>(prepared);
      runtime->open_devices();
      cycles = static_cast<int>(std::ceil(runtime->natural_duration() / period));
      cycle = 0;
      state.ResumeTiming();
    }
    const double t = cycle++ * period;
    const auto begin = std::chrono::steady_clock::now();
    runtime->world().cycle(t, t + period, [t] { return t; });
    times.push_back(
        std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - begin)
            .count());
  }
  state.counters["cycles_per_run"] = cycles;
  if (!times.empty()) report(state, std::move(times));
}
BENCHMARK(BM_PickAndPlaceScene)->MinTime(3.0);

}  // namespace
