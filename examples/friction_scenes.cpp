// Friction and free bodies from scene files (issue 20), with nothing but installed headers:
//  (g) examples/scenes/block_push.json: a held paddle pushes a free block across a table. The
//      block sticks until the push reaches μ_s m g, then slides: printed, the largest push before
//      it moved 1 mm against μ_s m g.
//  (h) examples/scenes/pick_and_place.json: a scripted operator picks a free peg off the table
//      with its grasp button, carries it to a plate, lowers it into the plate's hole and then
//      further down along one wall it pushes it against. Run with every contact's friction at 0.4,
//      as the scene says, and at 0: printed, the insertion force (the plate's push up on the hand's
//      gripper and peg) and where the peg ends.
// Usage: friction_scenes [BLOCK_PUSH.json PICK_AND_PLACE.json]. Units: m, s, N, kg.
#include <khz/reduced/worker_threads.hpp>
#include <khz/scene/cache_directory.hpp>
#include <khz/scene/prepare_scene.hpp>
#include <khz/scene/read_scene.hpp>
#include <khz/scene/scene_runtime.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

namespace ks = khz::scene;
namespace contact = khz::contact;
namespace haptic = khz::haptic;

namespace {

ks::PreparedScene prepare(const std::string& file) {
  ks::ProductCache cache(ks::default_cache_directory());
  std::printf("preparing %s\n", file.c_str());
  return ks::prepare_scene(ks::read_scene(file), cache);
}

int object_named(const ks::SceneDescription& scene, const std::string& name) {
  for (std::size_t i = 0; i < scene.objects.size(); ++i) {
    if (scene.objects[i].name == name) return static_cast<int>(i);
  }
  return -1;
}

/// Runs the scene's own duration; `each` sees every cycle's time and the runtime after it.
template <typename Each>
void run(ks::SceneRuntime& runtime, const Each& each) {
  runtime.open_devices();
  const double period = 1.0 / runtime.description().loop.rate_hz;
  const auto cycles = static_cast<int>(std::ceil(runtime.natural_duration() / period));
  for (int i = 0; i < cycles; ++i) {
    const double t = i * period;
    runtime.world().cycle(t, t + period, [t] { return t; });
    each(t, runtime);
  }
  runtime.close_devices();
}

/// The pair of the World that queries `a`'s pointshell against `b`'s field, or −1.
int pair_of(const haptic::World& world, int a, int b) {
  const auto pairs = world.pairs();
  for (std::size_t p = 0; p < pairs.size(); ++p) {
    if (pairs[p].pointshell == a && pairs[p].field == b) return static_cast<int>(p);
  }
  return -1;
}

void block_push(const std::string& file) {
  const ks::PreparedScene prepared = prepare(file);
  const int block = object_named(prepared.description, "block");
  const int table = object_named(prepared.description, "table");
  const double mass = prepared.objects[static_cast<std::size_t>(block)].mass_properties->mass;
  const double static_coefficient = prepared.description.pairs.at(0).friction.static_coefficient;
  ks::SceneRuntime runtime(prepared);
  const int on_table = pair_of(runtime.world(), block, table);
  // The block slides once most of its points on the table do (before that it gives elastically,
  // up to the stick distance μ_s h).
  double start = 0.0, largest_stuck_push = 0.0, slid_at = -1.0;
  run(runtime, [&](double t, ks::SceneRuntime& r) {
    const double x = r.world().motion(block)->centre().x();
    if (t < 0.3) start = x;  // settled on the table, not yet pushed
    const double push = -r.world().records()[0].contact.force.x();  // on the block, +x
    const contact::ContactStatistics& contact = r.world().pair_result(on_table).statistics;
    if (slid_at < 0.0 && 2 * contact.points_sliding > contact.points_in_contact) slid_at = t;
    if (slid_at < 0.0) largest_stuck_push = std::max(largest_stuck_push, push);
  });
  std::printf(
      "(g) the %.3g kg block stuck until the push reached %.4g N (mu_s m g = %.4g N, %+.2f %%), "
      "slid from t = %.3g s and moved %.3g m in all\n",
      mass, largest_stuck_push, static_coefficient * mass * 9.81,
      100.0 * (largest_stuck_push / (static_coefficient * mass * 9.81) - 1.0), slid_at,
      runtime.world().motion(block)->centre().x() - start);
}

void pick_and_place(const std::string& file) {
  ks::PreparedScene prepared = prepare(file);
  const int peg = object_named(prepared.description, "peg");
  const int plate = object_named(prepared.description, "plate");
  const double weight =
      prepared.objects[static_cast<std::size_t>(peg)].mass_properties->mass * 9.81;
  const double friction = prepared.description.contact.friction.static_coefficient;
  for (const double mu : {0.0, friction}) {
    prepared.description.contact.friction.static_coefficient = mu;
    prepared.description.contact.friction.kinetic_coefficient = mu;
    ks::SceneRuntime runtime(prepared);
    const double plate_top =
        prepared.description.objects[static_cast<std::size_t>(plate)].pose.position.z();
    double largest = 0.0, sum = 0.0, wall = 0.0;
    int inserting = 0;
    bool grasped = false;
    run(runtime, [&](double, ks::SceneRuntime& r) {
      grasped = grasped || r.world().hand_of(peg) == 0;
      // Inserting: grasped, the peg's bottom (its body origin) below the plate's top, moving
      // down (it rides with the hand: its motion is the hand's).
      if (r.world().hand_of(peg) == 0 && r.pose(peg).translation().z() < plate_top &&
          r.world().motion(peg)->velocity().z() < -0.005) {
        // The hand's contact wrench holds the grasped peg's weight too: without it, the plate's.
        const Eigen::Vector3d& force = r.world().records()[0].contact.force;
        const double up = force.z() + weight;
        largest = std::max(largest, up);
        sum += up;
        wall += -force.x();
        ++inserting;
      }
    });
    const Eigen::Vector3d end = runtime.pose(peg).translation();
    std::printf(
        "(h) friction %.1f: %s; inserting (%d cycles) against the wall's %.3g N, the plate "
        "resisted with %.3g N on average (%.2f of the wall's), %.3g N at most; the peg ends at "
        "[%.4f, %.4f, %.4f] m, %s\n",
        mu, grasped ? "grasped and carried" : "never grasped", inserting,
        inserting > 0 ? wall / inserting : 0.0, inserting > 0 ? sum / inserting : 0.0,
        wall > 0.0 ? sum / wall : 0.0, largest, end.x(), end.y(), end.z(),
        std::abs(end.x() - 0.08) < 0.002 && end.z() < plate_top ? "in the hole"
                                                                : "not in the hole");
  }
}

}  // namespace

int main(int argc, char** argv) {
  khz::reduced::set_worker_threads_from_environment();
  block_push(argc > 2 ? argv[1] : KHZ_EXAMPLE_SCENES "/block_push.json");
  pick_and_place(argc > 2 ? argv[2] : KHZ_EXAMPLE_SCENES "/pick_and_place.json");
}
