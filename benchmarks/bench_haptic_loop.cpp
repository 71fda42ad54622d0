// The haptic loop end to end (thesis §4.1, Fig. 4.2): what whole haptic cycles cost on the contact
// benchmarks' scenes with static virtual coupling, and how the loop keeps time at 1 kHz.
//
//   bench_haptic_loop [--seconds 60] [--loop-scene a|c] [--load spin|memory|none] [--cpu 0]
//                     [--cycles 8000] [--budget 300] [--costs-fifo] [--skip-costs] [--skip-loop]
//                     [--skip-world]
//
// A simulated operator (virtual device + hand, SimulatedOperator) holds dino.off, its 256³ signed
// field the haptic object as in the thesis, and its hand's anchor follows an 8 s script: from 3 cm
// apart it pushes 25 mm past contact into a fixed pointshell, slides ±6 cm across it while turning
// ±15° about the approach axis and rocking ±8°, and leaves. The coupling keeps the penetration
// shallow (its force saturates at the contact force of one point half a voxel deep, §4.9).
//
// Part 1, full-cycle costs: a one-hand haptic::World's cycle in a tight loop (no real-time
// thread; with --costs-fifo on --cpu at SCHED_FIFO, so other processes do not preempt it) for
//   a  a rigid pointshell: bunny00.off, 1.02M points in 6 levels;
//   b  a reduced deformable one: ChineseDragon-10kv.off, 262k points in 5 levels, r = 15 (its voxel
//      mesh anchored at its lowest 8%), stepped by make_reduced_newmark()'s integrator under the
//      contact's reduced force every cycle;
//   c  a with the query's time budget (--budget, µs; graceful degradation, §3.10.3).
// Per cycle (µs: mean, p50, p99, max, over all cycles and over those in contact): the contact
// query (its own ContactStatistics::microseconds), the integrator step (timed on a twin
// integrator stepped after the cycle under the same reduced force: the same arithmetic, with the
// model's coefficients just read, so if anything a lower bound), device I/O (the simulated
// device's read and write, timed inside a Device wrapper), and the rest: the coupling step, the
// safety layer and the cycle's bookkeeping (whole cycle minus query and device I/O, minus the
// twin's step).
//
// Part 2, the real-time loop: HapticLoop at 1 kHz for --seconds running scene c's cycle (or a's)
// while a busy thread loads the other core: first pinned to CPU --cpu (0) with SCHED_FIFO requested
// and the load pinned to the next CPU, then unpinned at normal priority with the load free too.
// It reports the loop's work time (p50/p99/max), its latest start, deadline misses and skipped
// periods, whether the priority and pin took effect (as the loop's thread sees itself), the
// lateness of each wake-up, and which misses came from late wake-ups and which from long work.
//
// Part 3, the multi-body runtime: scene a's pair as one cycle of a haptic::World against the same
// pair's cycle written out from the library's calls (query_contact, VirtualCoupling::step,
// SafeDevice read and write: the single-object cycle as the thesis runs it), alternating cycle by
// cycle (the ratio says whether the World costs more for one pair); then a World of three bodies
// and two hands (the held dino, a bunny held still by a second operator where scene a's stands, and
// a fixed bunny facing the dino's other flank): mean and p99 of the whole cycle.
//
// Per-cycle rows of every run go to <build>/benchmarks/haptic_loop_runs/*.csv. Meshes, fields,
// pointshells, trees and bases come from bench_contact_query's cache (KHZ_CONTACT_CACHE_DIR); the
// dragon's reduced model is cached there too.
#include "contact_scenes.hpp"

#include <khz/contact/query/contact_query.hpp>
#include <khz/haptic/coupling/virtual_coupling.hpp>
#include <khz/haptic/device/safe_device.hpp>
#include <khz/haptic/device/simulated_operator.hpp>
#include <khz/haptic/loop/haptic_loop.hpp>
#include <khz/haptic/world/world.hpp>
#include <khz/reduced/io/reduced_model_file.hpp>
#include <khz/reduced/subspace/polynomial_forces.hpp>
#include <khz/reduced/subspace/reduced_model.hpp>

#include <pthread.h>
#include <sched.h>
#include <sys/resource.h>
#include <unistd.h>
#include <CLI/CLI.hpp>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <functional>
#include <limits>
#include <memory>
#include <numbers>
#include <span>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace {

namespace kc = khz::contact;
namespace kh = khz::haptic;
namespace kr = khz::reduced;
using khz::bench::Clock;
using khz::bench::degrees;
using khz::bench::quantile;

constexpr double period = 1e-3;  // s: the haptic loop's 1 kHz

double microseconds(Clock::duration d) {
  return std::chrono::duration<double, std::micro>(d).count();
}

// ---------------------------------------------------------------------------------------------
// Timing wrapper: the device I/O of a cycle.

/// Times the reads and writes of the device it wraps.
class TimedDevice final : public kh::Device {
 public:
  explicit TimedDevice(kh::Device& device) noexcept : m_device(device) {}

  void open() override { m_device.open(); }
  void close() noexcept override { m_device.close(); }
  bool is_open() const noexcept override { return m_device.is_open(); }
  const kh::DeviceCapabilities& capabilities() const noexcept override {
    return m_device.capabilities();
  }
  bool read(kh::DeviceState& state) noexcept override {
    const Clock::time_point start = Clock::now();
    const bool ok = m_device.read(state);
    io_time += Clock::now() - start;
    return ok;
  }
  bool write(const kh::Wrench& wrench) noexcept override {
    const Clock::time_point start = Clock::now();
    const bool ok = m_device.write(wrench);
    io_time += Clock::now() - start;
    return ok;
  }

  Clock::duration io_time{};  // read + write of the current cycle

 private:
  kh::Device& m_device;
};

// ---------------------------------------------------------------------------------------------
// Scenes: a fixed pointshell touching the held dino.

const kc::TriangleMesh& dino_mesh() {
  static const kc::TriangleMesh mesh = khz::bench::demo_mesh("dino.off", 1.0);
  return mesh;
}

const kc::DistanceGrid& dino_field() {
  static const kc::DistanceGrid field = khz::bench::cached_signed_field("dino", dino_mesh(), 256);
  return field;
}

double voxel() { return dino_field().geometry().spacing; }

/// Where a scene's pointshell sits (world), touching the dino at rest (the identity) from +x; the
/// grasp point (the dino's body coordinates) is the pointshell point nearest the dino's surface.
struct Placement {
  Eigen::Isometry3d pointshell = Eigen::Isometry3d::Identity();
  Eigen::Vector3d grasp = Eigen::Vector3d::Zero();
  double object_radius = 0.0;  // the dino's farthest vertex from the grasp point (m)
};

Placement touching_dino(const kc::PointTree& tree, double height) {
  const khz::bench::RigidShape shape(tree);
  const auto at = [height](double u) {
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.translation() = Eigen::Vector3d(u, height, 0.0);
    return pose;
  };
  Placement placement;
  placement.pointshell = at(khz::bench::solve_increasing(
      [&](double u) { return khz::bench::min_distance(shape, dino_field(), at(u)); }, 1.0,
      0.25 * voxel(), 1e-3 * voxel()));
  double nearest = std::numeric_limits<double>::infinity();
  for (Eigen::Index s = 0; s < tree.num_points(); ++s) {
    const Eigen::Vector3d p = placement.pointshell * shape.position(s);
    const double d = dino_field().distance(p);
    if (d < nearest) nearest = d, placement.grasp = p;
  }
  placement.object_radius =
      (dino_mesh().vertices.rowwise() - placement.grasp.transpose()).rowwise().norm().maxCoeff();
  return placement;
}

/// A scene ready to run: the fixed pointshell body the held dino touches, and a deformable
/// pointshell's dynamics.
struct SceneInstance {
  std::unique_ptr<kr::PolynomialForces> forces;
  /// The deformable pointshell's integrator (the World steps it), and a twin stepped beside it
  /// under the same reduced forces to time a step; both null for a rigid pointshell.
  std::unique_ptr<kr::ReducedIntegrator> integrator, twin;
  kh::Body pointshell;
  /// The deepest penetration (m, ≥ 0) with the dino's grasp frame at `grasp`.
  std::function<double(const kh::Pose& grasp)> depth;
  /// A deformable pointshell's largest vertex displacement now (m); empty for a rigid one.
  std::function<double()> deformation;
};

struct SceneSpec {
  std::string name;
  Placement placement;
  kc::ContactOptions contact;
  std::function<SceneInstance(const kc::ContactOptions&)> make;
  const kc::PointTree* rigid_tree = nullptr;  // the pointshell of a rigid one
};

/// A rigid pointshell body at `pose` (world ← body).
kh::Body rigid_pointshell(std::string name, const kc::PointTree& tree,
                          const Eigen::Isometry3d& pose) {
  kh::Body body;
  body.name = std::move(name);
  body.pose = pose;
  body.pointshell = &tree;
  return body;
}

/// A and C: bunny00.off (0.5 m) as a 1.02M-point, 6-level pointshell beside the dino's flank.
SceneSpec bunny_scene(const std::string& name, const kc::ContactOptions& contact) {
  static const kc::PointTree tree(khz::bench::cached_pointshell(
      "bunny", khz::bench::demo_mesh("bunny00.off", 0.5), false, 256, 750, 6));
  static const Placement placement = touching_dino(tree, 0.05);
  SceneSpec spec{name, placement, contact, {}, &tree};
  spec.make = [](const kc::ContactOptions&) {
    SceneInstance s;
    s.pointshell = rigid_pointshell("bunny", tree, placement.pointshell);
    s.depth = [](const kh::Pose& grasp) {
      return std::max(
          0.0, -khz::bench::min_distance(
                   khz::bench::RigidShape(tree), dino_field(),
                   kh::held_body_pose(grasp, placement.grasp).inverse() * placement.pointshell));
    };
    return s;
  };
  return spec;
}

/// The dragon's r = 15 reduced model (the cached basis's material), cached as a model file.
const kr::ReducedModel& dragon_model(const kr::VolumeMesh& volume, const kr::Basis& basis) {
  static const kr::ReducedModel model = khz::bench::cached(
      "dragon_voxel32_r15.khzmodel",
      [&] {
        const kr::FemModel fem(volume, {kr::Material::stvk(1e6, 0.4, 1000.0)});
        return kr::ReducedModel::precompute(fem, basis);
      },
      [&](const std::filesystem::path& p) { return kr::read_reduced_model(p, volume); },
      [&](const std::filesystem::path& p, const kr::ReducedModel& m) {
        kr::write_reduced_model(p, m, volume);
      });
  return model;
}

/// B: ChineseDragon-10kv.off (0.5 m), reduced deformable (r = 15), beside the dino's flank.
SceneSpec dragon_scene(const kc::ContactOptions& contact) {
  static const kc::TriangleMesh mesh = khz::bench::demo_mesh("ChineseDragon-10kv.off", 0.5);
  static const kr::VolumeMesh volume = khz::bench::voxel_volume(mesh);
  static const kr::Basis basis =
      khz::bench::cached_basis("dragon_voxel32", volume, khz::bench::lowest_vertices(volume), 15);
  static const kc::DeformablePointTree tree = khz::bench::cached_deformable_tree(
      "dragon_262229_L5_voxel32_r15",
      [&] { return khz::bench::cached_pointshell("dragon", mesh, true, 256, 769, 5); }, volume,
      basis);
  static const kr::ReducedModel& model = dragon_model(volume, basis);
  static const Placement placement = touching_dino(tree.tree(), 0.0);
  SceneSpec spec{"b deformable dragon 262k r=15", placement, contact, {}};
  spec.make = [](const kc::ContactOptions&) {
    SceneInstance s;
    s.forces = std::make_unique<kr::PolynomialForces>(model.energy_polynomial());
    kr::ReducedNewmarkOptions newmark = model.defaults().newmark_options();
    newmark.newmark.time_step = period;
    newmark.newmark.mass_damping = 1.0;  // a little damping, so contact does not ring for long
    newmark.newmark.stiffness_damping = 1e-3;
    s.integrator = kr::make_reduced_newmark(*s.forces, model.mass(), newmark);
    s.twin = kr::make_reduced_newmark(*s.forces, model.mass(), newmark);
    s.pointshell.name = "dragon";
    s.pointshell.pose = placement.pointshell;
    s.pointshell.pointshell = &tree;
    s.pointshell.integrator = s.integrator.get();
    s.deformation = [integrator = s.integrator.get()] {
      const Eigen::VectorXd u = basis.vectors * integrator->coordinates();
      return Eigen::Map<const Eigen::Matrix3Xd>(u.data(), 3, u.size() / 3)
          .colwise()
          .norm()
          .maxCoeff();
    };
    s.depth = [integrator = s.integrator.get()](const kh::Pose& grasp) {
      return std::max(
          0.0, -khz::bench::min_distance(
                   khz::bench::DeformedShape(tree, integrator->coordinates()), dino_field(),
                   kh::held_body_pose(grasp, placement.grasp).inverse() * placement.pointshell));
    };
    return s;
  };
  return spec;
}

// ---------------------------------------------------------------------------------------------
// The operator, the coupling and the cycle.

constexpr double script_seconds = 8.0;

/// The hand's anchor in device coordinates (the grasp point at rest at the origin), repeating
/// every script_seconds: pushes 25 mm past contact along +x, slides, turns and rocks, leaves.
kh::TargetFunction hand_target() {
  const auto pose = [](double x, double y, double z, double turn, double rock) {
    kh::Pose p;
    p.position = Eigen::Vector3d(x, y, z);
    p.orientation = Eigen::AngleAxisd(turn * degrees, Eigen::Vector3d::UnitX()) *
                    Eigen::AngleAxisd(rock * degrees, Eigen::Vector3d::UnitZ());
    return p;
  };
  const double apart = -0.03, push = 0.025;
  const kh::TargetFunction script = kh::keyframe_target({
      {0.0, pose(apart, 0.0, 0.0, 0.0, 0.0)},
      {0.3, pose(apart, 0.0, 0.0, 0.0, 0.0)},
      {1.0, pose(push, 0.0, 0.0, 0.0, 0.0)},
      {2.2, pose(push, 0.0, 0.06, 0.0, 0.0)},
      {3.4, pose(push, 0.03, 0.06, 15.0, 8.0)},
      {4.8, pose(push, -0.02, -0.06, -15.0, -8.0)},
      {6.0, pose(push, 0.0, 0.0, 0.0, 0.0)},
      {7.0, pose(apart, 0.0, 0.0, 0.0, 0.0)},
      {script_seconds, pose(apart, 0.0, 0.0, 0.0, 0.0)},
  });
  return [script](double time) { return script(std::fmod(time, script_seconds)); };
}

/// Static virtual coupling for the held dino (§4.3–§4.10): k_VC 500 N/m, the force saturating at
/// one point's contact force half a voxel deep (§4.9), the device's limits.
kh::CouplingOptions coupling_options(const kc::ContactOptions& contact, const Placement& placement,
                                     const kh::DeviceCapabilities& device) {
  kh::CouplingOptions o;
  o.stiffness = 500.0;
  o.period = period;
  o.saturation_force = contact.stiffness * 0.5 * voxel();
  o.object_radius = placement.object_radius;
  o.max_rendered_force = device.max_force;
  o.max_rendered_torque = device.max_torque;
  o.device_max_stiffness = device.max_stiffness;
  return o;
}

/// The grasp frame the script starts at (world): its first anchor, moved to the dino's grasp.
kh::Pose script_start(const Placement& placement) {
  kh::Pose p = hand_target()(0.0);
  p.position += placement.grasp;
  return p;
}

/// The held dino (its 256³ field the haptic object), placed at the script's start.
kh::Body held_dino(const Placement& placement) {
  kh::Body body;
  body.name = "dino";
  body.field = &dino_field();
  body.pose = kh::held_body_pose(script_start(placement), placement.grasp);
  return body;
}

/// A device mapping that puts the device's origin at `origin` (world).
kh::WorkspaceMapping origin_at(const Eigen::Vector3d& origin) {
  kh::WorkspaceMapping m;
  m.offset.position = origin;
  return m;
}

/// A hand holding body `body` at `grasp` (its body frame) through `device`.
kh::Hand holding(int body, const Eigen::Vector3d& grasp, kh::SafeDevice& device,
                 const kh::CouplingOptions& coupling) {
  kh::Hand hand;
  hand.body = body;
  hand.grasp_in_body = grasp;
  hand.device = &device;
  hand.coupling = coupling;
  return hand;
}

/// One scene's haptic cycle: a World of the held dino and the scene's pointshell, one simulated
/// operator's hand holding the dino.
class Rig {
 public:
  Rig(const SceneSpec& spec, const kc::ContactOptions& contact)
      : m_instance(spec.make(contact)),
        m_operator(hand_target()),
        m_device(m_operator),
        m_safe(m_device, {}, origin_at(spec.placement.grasp)),
        m_world({held_dino(spec.placement), m_instance.pointshell},
                {holding(0, spec.placement.grasp, m_safe,
                         coupling_options(contact, spec.placement, m_operator.capabilities()))},
                contact) {
    m_safe.open();
  }

  /// One cycle at `now` (s); `clock` reads the same clock. Then a deformable pointshell's twin
  /// integrator takes the same step, timed (integrator_time()).
  template <typename ClockFunction>
  const kh::CycleRecord& run(double now, ClockFunction&& clock) noexcept {
    m_device.io_time = {};
    const kh::CycleRecord& record = m_world.cycle(now, now + period, clock)[0];
    m_integrator_time = {};
    if (m_instance.twin != nullptr) {
      const Clock::time_point start = Clock::now();
      m_instance.twin->step(m_world.reduced_force(1));
      m_integrator_time = Clock::now() - start;
    }
    return record;
  }

  /// The last cycle's contact query (µs, as the query measured itself).
  double query_microseconds() const noexcept {
    return m_world.records()[0].contact.statistics.microseconds;
  }
  /// The twin integrator's step after the last cycle (zero for a rigid pointshell).
  Clock::duration integrator_time() const noexcept { return m_integrator_time; }
  const TimedDevice& device() const noexcept { return m_device; }
  const kh::SafeDevice& safe() const noexcept { return m_safe; }
  const SceneInstance& instance() const noexcept { return m_instance; }

 private:
  SceneInstance m_instance;
  kh::SimulatedOperator m_operator;
  TimedDevice m_device;
  kh::SafeDevice m_safe;
  kh::World m_world;
  Clock::duration m_integrator_time{};
};

// ---------------------------------------------------------------------------------------------
// Part 1: full-cycle costs.

struct Spread {
  double mean = 0, p50 = 0, p99 = 0, max = 0;
};

Spread spread(const std::vector<double>& values) {
  Spread s;
  if (values.empty()) return s;
  for (const double v : values) s.mean += v / static_cast<double>(values.size());
  s.p50 = quantile(values, 0.5);
  s.p99 = quantile(values, 0.99);
  s.max = *std::max_element(values.begin(), values.end());
  return s;
}

enum Part { whole, query, integrator, device_io, coupling_rest, part_count };
constexpr std::array<const char*, part_count> part_names = {
    "whole cycle", "contact query", "integrator step", "device I/O", "coupling + rest"};

/// Appends one CSV row: the values, comma-separated.
template <typename... Values>
void append_row(std::string& csv, const Values&... values) {
  const char* separator = "";
  ((csv += separator, csv += std::to_string(values), separator = ","), ...);
  csv += '\n';
}

struct CostRun {
  std::string name;
  std::array<std::vector<double>, part_count> all, in_contact;  // µs per cycle
  std::vector<double> nodes, contacts;                          // cycles in contact
  std::array<long, 8> deepest_levels{};                         // cycles in contact
  long incomplete = 0;                                          // degraded queries
  long failures = 0;  // cycles whose device, query, coupling or integrator failed
  long safety_misses = 0;
  double deepest_penetration = 0.0;  // m, sampled every 20th cycle
  double strongest_rendered = 0.0;   // N
  double largest_deformation = 0.0;  // m, sampled every 20th cycle (deformable pointshell)
  std::size_t cycles = 0;
};

/// Runs `cycles` cycles of the scene back to back on the loop's virtual clock (cycle i at
/// i·period; the watchdog sees the real duration). `pause`: sleep 1 ms after every 10 ms of
/// running, so a SCHED_FIFO thread stays below the kernel's real-time throttling (95% of each
/// second by default; beyond it the thread is stopped for the rest of the second).
CostRun run_costs(const SceneSpec& spec, int cycles, bool pause) {
  std::printf("  %s: %d cycles ...\n", spec.name.c_str(), cycles);
  std::fflush(stdout);
  Rig rig(spec, spec.contact);
  CostRun run;
  run.name = spec.name;
  run.cycles = static_cast<std::size_t>(cycles);
  std::string csv =
      "cycle,whole_us,query_us,integrator_us,device_us,rest_us,nodes,contacts,deepest,"
      "complete,rendered_N\n";
  Clock::time_point running_since = Clock::now();
  for (int i = 0; i < cycles; ++i) {
    if (pause && Clock::now() - running_since > std::chrono::milliseconds(10)) {
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
      running_since = Clock::now();
    }
    const double now = i * period;
    const Clock::time_point start = Clock::now();
    const kh::CycleRecord& r = rig.run(now, [&] { return now + khz::bench::seconds_since(start); });
    const double total = microseconds(Clock::now() - start);
    std::array<double, part_count> us{};
    us[integrator] = microseconds(rig.integrator_time());
    us[whole] = total - us[integrator];  // the twin's step ran after the World's cycle
    us[query] = rig.query_microseconds();
    us[device_io] = microseconds(rig.device().io_time);
    us[coupling_rest] = us[whole] - us[query] - us[integrator] - us[device_io];
    const bool touching = r.contact.statistics.points_in_contact > 0;
    for (int p = 0; p < part_count; ++p) {
      run.all[p].push_back(us[p]);
      if (touching) run.in_contact[p].push_back(us[p]);
    }
    if (!(r.device_valid && r.contact_valid && r.coupling_valid && r.integrators_ok)) {
      ++run.failures;
    }
    if (touching) {
      run.nodes.push_back(static_cast<double>(r.contact.statistics.nodes_traversed));
      run.contacts.push_back(static_cast<double>(r.contact.statistics.points_in_contact));
      ++run.deepest_levels[static_cast<std::size_t>(
          std::clamp(r.contact.statistics.deepest_level, 0, 7))];
    }
    if (!r.contact.statistics.complete) ++run.incomplete;
    append_row(csv, i, us[whole], us[query], us[integrator], us[device_io], us[coupling_rest],
               r.contact.statistics.nodes_traversed, r.contact.statistics.points_in_contact,
               r.contact.statistics.deepest_level, int{r.contact.statistics.complete},
               r.rendered.force.norm());
    run.strongest_rendered = std::max(run.strongest_rendered, r.rendered.force.norm());
    if (i % 20 == 0) {
      run.deepest_penetration =
          std::max(run.deepest_penetration, rig.instance().depth(r.simulation));
      if (rig.instance().deformation) {
        run.largest_deformation = std::max(run.largest_deformation, rig.instance().deformation());
      }
    }
  }
  run.safety_misses = static_cast<long>(rig.safe().statistics().deadline_misses);
  khz::bench::write_run_csv("haptic_loop_runs", "cycles " + spec.name, csv);
  return run;
}

void print_costs(const std::vector<CostRun>& runs) {
  std::printf(
      "\nFull haptic cycle, back to back on one core (µs; 'rest' = coupling step, safety layer\n"
      "and bookkeeping = whole − query − integrator − device I/O):\n");
  std::printf("%-34s %-16s %8s %8s %8s %8s | %8s %8s %8s %8s\n", "scene", "part", "mean", "p50",
              "p99", "max", "mean", "p50", "p99", "max");
  std::printf("%-34s %-16s %35s | %35s\n", "", "", "all cycles", "cycles in contact");
  for (const CostRun& run : runs) {
    for (int p = 0; p < part_count; ++p) {
      const Spread a = spread(run.all[p]), c = spread(run.in_contact[p]);
      std::printf("%-34s %-16s %8.1f %8.1f %8.1f %8.1f | %8.1f %8.1f %8.1f %8.1f\n",
                  p == 0 ? run.name.c_str() : "", part_names[static_cast<std::size_t>(p)], a.mean,
                  a.p50, a.p99, a.max, c.mean, c.p50, c.p99, c.max);
    }
  }
  std::printf(
      "\nContact per cycle (cycles in contact); deepest penetration (voxels h) and largest\n"
      "deformation (mm), sampled every 20th cycle; largest rendered force (N); degraded queries;\n"
      "failed cycles; cycles the safety layer saw end late; the deepest level rendered:\n");
  std::printf("%-34s %7s %6s %8s %8s %8s %8s %8s %7s %6s %7s %6s %5s %s\n", "scene", "cycles",
              "cont%", "nodes", "nodes mx", "contacts", "cont mx", "pen/h mx", "def mm", "|F|mx",
              "degrad", "fails", "miss", "deepest level × cycles");
  for (const CostRun& run : runs) {
    const Spread nodes = spread(run.nodes), contacts = spread(run.contacts);
    std::printf("%-34s %7zu %6.1f %8.0f %8.0f %8.0f %8.0f %8.3f %7.2f %6.2f %7ld %6ld %5ld ",
                run.name.c_str(), run.cycles,
                100.0 * static_cast<double>(run.nodes.size()) / static_cast<double>(run.cycles),
                nodes.mean, nodes.max, contacts.mean, contacts.max,
                run.deepest_penetration / voxel(), 1e3 * run.largest_deformation,
                run.strongest_rendered, run.incomplete, run.failures, run.safety_misses);
    for (std::size_t level = 0; level < run.deepest_levels.size(); ++level) {
      if (run.deepest_levels[level] > 0) std::printf(" L%zu×%ld", level, run.deepest_levels[level]);
    }
    std::printf("\n");
  }
}

// ---------------------------------------------------------------------------------------------
// Priority and pinning of the calling thread (--costs-fifo).

/// Pins the calling thread to `cpu` at SCHED_FIFO `priority`; false if either is refused.
bool realtime_on_cpu(int cpu, int priority) {
  cpu_set_t set;
  CPU_ZERO(&set);
  CPU_SET(cpu, &set);
  sched_param parameter{};
  parameter.sched_priority = priority;
  return pthread_setaffinity_np(pthread_self(), sizeof(set), &set) == 0 &&
         pthread_setschedparam(pthread_self(), SCHED_FIFO, &parameter) == 0;
}

/// Back to normal priority on any CPU.
void normal_priority() {
  cpu_set_t set;
  CPU_ZERO(&set);
  for (unsigned cpu = 0; cpu < std::thread::hardware_concurrency(); ++cpu) CPU_SET(cpu, &set);
  const sched_param parameter{};
  pthread_setschedparam(pthread_self(), SCHED_OTHER, &parameter);
  pthread_setaffinity_np(pthread_self(), sizeof(set), &set);
}

// ---------------------------------------------------------------------------------------------
// Part 2: the real-time loop.

/// Keeps one CPU busy until destroyed: a chain of floating-point operations in registers
/// ("spin"), or that while streaming through 64 MiB ("memory", which also evicts the shared
/// cache the loop's tree and field live in). `cpu` < 0 leaves it free.
class BusyThread {
 public:
  BusyThread(int cpu, bool memory) : m_thread([this, cpu, memory] { run(cpu, memory); }) {}
  ~BusyThread() {
    m_stop.store(true);
    m_thread.join();
  }
  BusyThread(const BusyThread&) = delete;
  BusyThread& operator=(const BusyThread&) = delete;

  std::uint64_t rounds() const noexcept { return m_rounds.load(); }
  bool pinned() const noexcept { return m_pinned.load(); }

 private:
  void run(int cpu, bool memory) {
    if (cpu >= 0) {
      cpu_set_t set;
      CPU_ZERO(&set);
      CPU_SET(cpu, &set);
      m_pinned.store(pthread_setaffinity_np(pthread_self(), sizeof(set), &set) == 0);
    }
    std::vector<double> buffer(memory ? (std::size_t{64} << 20) / sizeof(double) : 1, 1.0);
    double x = 1.0;
    while (!m_stop.load(std::memory_order_relaxed)) {
      for (int k = 0; k < 4096; ++k) x = x * 0.9999999 + 1e-7;
      if (memory) {
        for (double& b : buffer) b = b * 0.5 + x;
      }
      m_rounds.fetch_add(1, std::memory_order_relaxed);
    }
    m_sink.store(x + buffer.front());
  }

  std::atomic<bool> m_stop{false};
  std::atomic<bool> m_pinned{false};
  std::atomic<std::uint64_t> m_rounds{0};
  std::atomic<double> m_sink{0.0};
  std::thread m_thread;  // last: starts once the members above exist
};

std::string load_average() {
  std::ifstream file("/proc/loadavg");
  double one = 0, five = 0, fifteen = 0;
  file >> one >> five >> fifteen;
  char text[64];
  std::snprintf(text, sizeof text, "%.2f, %.2f, %.2f", one, five, fifteen);
  return text;
}

/// Per CPU, the time (s) the hypervisor ran something else (steal) and spent in interrupts
/// (irq + softirq), from /proc/stat.
struct CpuTimes {
  std::array<double, 2> steal{}, interrupts{};
};

CpuTimes cpu_times() {
  std::ifstream file("/proc/stat");
  CpuTimes times;
  std::string line;
  while (std::getline(file, line)) {
    std::istringstream fields(line);
    std::string name;
    std::array<double, 8> ticks{};  // user nice system idle iowait irq softirq steal
    fields >> name;
    for (double& t : ticks) fields >> t;
    if (name == "cpu0" || name == "cpu1") {
      const auto cpu = static_cast<std::size_t>(name[3] - '0');
      const double tick = 1.0 / static_cast<double>(sysconf(_SC_CLK_TCK));
      times.steal[cpu] = tick * ticks[7];
      times.interrupts[cpu] = tick * (ticks[5] + ticks[6]);
    }
  }
  return times;
}

struct LoopRunOptions {
  double seconds = 60.0;
  bool pinned = true;  // loop on `cpu` with SCHED_FIFO requested, the load on the next CPU
  int cpu = 0;
  int priority = 80;
  std::string load = "spin";
};

/// What the loop's cycle records about itself, preallocated (the cycle must not allocate).
struct LoopTrace {
  explicit LoopTrace(std::size_t capacity)
      : woke(capacity), work(capacity), query(capacity), contacts(capacity) {}
  std::vector<double> woke;         // µs after the scheduled start, up to cycle 0's own lateness
  std::vector<double> work, query;  // µs
  std::vector<std::int64_t> contacts;
  std::int64_t degraded = 0;  // queries the time budget stopped short
  std::array<std::int64_t, 64> cycles_on_cpu{};
  int policy = -1;  // as the loop's thread sees itself
  std::size_t size = 0;
};

void run_loop(const SceneSpec& spec, const LoopRunOptions& options) {
  const bool pinned = options.pinned;
  const int load_cpu = (options.cpu + 1) % static_cast<int>(std::thread::hardware_concurrency());
  std::printf(
      "\nLoop: %s at 1 kHz for %.0f s, %s; load: %s%s\n", spec.name.c_str(), options.seconds,
      pinned ? ("pinned to CPU " + std::to_string(options.cpu) + ", SCHED_FIFO requested").c_str()
             : "unpinned, normal priority",
      options.load.c_str(),
      options.load == "none"
          ? ""
          : (pinned ? (" thread pinned to CPU " + std::to_string(load_cpu)).c_str()
                    : " thread, free"));
  std::printf("  load average before: %s\n", load_average().c_str());
  std::fflush(stdout);

  Rig rig(spec, spec.contact);
  kh::LoopOptions loop_options;
  loop_options.rate_hz = 1.0 / period;
  loop_options.realtime_priority = pinned;
  loop_options.priority = options.priority;
  loop_options.cpu = pinned ? options.cpu : -1;
  kh::HapticLoop loop(loop_options);
  LoopTrace trace(static_cast<std::size_t>(options.seconds / period) + 1000);
  Clock::time_point origin;  // the loop's time 0, from cycle 0's wake-up

  const CpuTimes times_before = cpu_times();
  rusage usage_before{};
  getrusage(RUSAGE_SELF, &usage_before);
  auto busy = options.load == "none"
                  ? nullptr
                  : std::make_unique<BusyThread>(pinned ? load_cpu : -1, options.load == "memory");
  loop.start([&](const kh::CycleClock& clock) {
    const Clock::time_point woke = Clock::now();
    if (clock.cycle == 0) {
      origin = woke - std::chrono::duration_cast<Clock::duration>(
                          std::chrono::duration<double>(clock.time));
      trace.policy = sched_getscheduler(0);
    }
    const kh::CycleRecord& r =
        rig.run(clock.time, [&] { return khz::bench::seconds_since(origin); });
    const auto i = static_cast<std::size_t>(clock.cycle);
    if (i < trace.woke.size()) {
      trace.woke[i] = microseconds(woke - origin) - 1e6 * clock.time;
      trace.work[i] = microseconds(Clock::now() - woke);
      trace.query[i] = rig.query_microseconds();
      trace.contacts[i] = r.contact.statistics.points_in_contact;
      trace.size = i + 1;
    }
    if (!r.contact.statistics.complete) ++trace.degraded;
    const int cpu = sched_getcpu();
    if (cpu >= 0 && cpu < static_cast<int>(trace.cycles_on_cpu.size())) {
      ++trace.cycles_on_cpu[static_cast<std::size_t>(cpu)];
    }
  });
  const Clock::time_point started = Clock::now();
  double next_report = 10.0;
  while (loop.running() && khz::bench::seconds_since(started) < options.seconds) {
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    if (khz::bench::seconds_since(started) >= next_report) {
      const kh::LoopStatistics s = loop.statistics();
      std::printf("    %3.0f s: %ld cycles, p99 %.0f µs, max %.0f µs, misses %ld\n", next_report,
                  static_cast<long>(s.cycles), s.p99_work, s.max_work,
                  static_cast<long>(s.deadline_misses));
      std::fflush(stdout);
      next_report += 10.0;
    }
  }
  loop.stop();
  const std::uint64_t load_rounds = busy ? busy->rounds() : 0;
  const std::string load_thread = !busy            ? "none"
                                  : busy->pinned() ? "pinned to CPU " + std::to_string(load_cpu)
                                                   : "free";
  busy.reset();
  const CpuTimes times_after = cpu_times();
  rusage usage_after{};
  getrusage(RUSAGE_SELF, &usage_after);

  const kh::LoopStatistics s = loop.statistics();
  std::printf("  load average after:  %s\n", load_average().c_str());
  if (!loop.error().empty()) std::printf("  the cycle threw: %s\n", loop.error().c_str());
  for (const std::string& w : loop.warnings()) std::printf("  warning: %s\n", w.c_str());
  std::printf("  loop thread: %s; cycles per CPU:",
              trace.policy == SCHED_FIFO    ? "SCHED_FIFO (granted)"
              : trace.policy == SCHED_OTHER ? "SCHED_OTHER"
                                            : "another policy");
  for (std::size_t cpu = 0; cpu < trace.cycles_on_cpu.size(); ++cpu) {
    if (trace.cycles_on_cpu[cpu] > 0) {
      std::printf(" CPU%zu×%ld", cpu, static_cast<long>(trace.cycles_on_cpu[cpu]));
    }
  }
  std::printf(
      "\n  load thread: %s, %.3g rounds; during the run: steal CPU0 %.2f s, CPU1 %.2f s; "
      "interrupts CPU0 %.2f s, CPU1 %.2f s; page faults %ld minor, %ld major\n",
      load_thread.c_str(), static_cast<double>(load_rounds),
      times_after.steal[0] - times_before.steal[0], times_after.steal[1] - times_before.steal[1],
      times_after.interrupts[0] - times_before.interrupts[0],
      times_after.interrupts[1] - times_before.interrupts[1],
      usage_after.ru_minflt - usage_before.ru_minflt,
      usage_after.ru_majflt - usage_before.ru_majflt);

  // Wake-ups relative to the earliest one (cycle 0's own lateness is unknown; the earliest
  // wake-up of thousands is within a few µs of its schedule).
  trace.woke.resize(trace.size);
  trace.work.resize(trace.size);
  trace.query.resize(trace.size);
  trace.contacts.resize(trace.size);
  const double earliest = *std::min_element(trace.woke.begin(), trace.woke.end());
  long touching = 0, late_wakeups = 0, long_work = 0;
  std::string csv = "cycle,woke_late_us,work_us,query_us,contacts\n";
  for (std::size_t i = 0; i < trace.size; ++i) {
    trace.woke[i] -= earliest;
    touching += trace.contacts[i] > 0 ? 1 : 0;
    if (trace.woke[i] + trace.work[i] > 1e6 * period) {
      ++(trace.work[i] > 1e6 * period ? long_work : late_wakeups);
    }
    append_row(csv, i, trace.woke[i], trace.work[i], trace.query[i], trace.contacts[i]);
  }
  khz::bench::write_run_csv("haptic_loop_runs",
                            std::string("loop ") + (pinned ? "pinned " : "unpinned ") + spec.name,
                            csv);
  const Spread late = spread(trace.woke), q = spread(trace.query);
  std::printf(
      "  cycles %ld (%.1f%% in contact); work µs: mean %.1f, p50 %.0f, p99 %.0f, max %.0f\n",
      static_cast<long>(s.cycles),
      100.0 * static_cast<double>(touching) / static_cast<double>(trace.size), s.mean_work,
      s.p50_work, s.p99_work, s.max_work);
  std::printf(
      "  start lateness µs: loop's max %.0f; the cycle's own p50 %.0f, p99 %.0f, max %.0f\n",
      s.max_start_lateness, late.p50, late.p99, late.max);
  std::printf(
      "  deadline misses %ld (the cycle's own count: %ld from late wake-ups, %ld from work "
      "> 1 ms), skipped periods %ld\n",
      static_cast<long>(s.deadline_misses), late_wakeups, long_work,
      static_cast<long>(s.skipped_cycles));
  std::printf("  safety layer: %lu late cycles, %lu zeroed writes\n",
              static_cast<unsigned long>(rig.safe().statistics().deadline_misses),
              static_cast<unsigned long>(rig.safe().statistics().zeroed_writes));
  std::printf(
      "  contact query within the loop µs: mean %.1f, p50 %.1f, p99 %.1f, max %.1f; %ld degraded\n",
      q.mean, q.p50, q.p99, q.max, static_cast<long>(trace.degraded));
  std::printf("  targets: p99 < 1000 µs %s; no deadline misses %s\n",
              s.p99_work < 1000.0 ? "met" : "NOT met", s.deadline_misses == 0 ? "met" : "NOT met");
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Part 3: the multi-body World.

/// A hand of a World: a simulated operator following `target` behind its safety layer, whose
/// device origin is the world point `origin` (the held body's grasp point at rest).
struct OperatorHand {
  OperatorHand(kh::TargetFunction target, const Eigen::Vector3d& origin)
      : device(std::move(target)), safe(device, {}, origin_at(origin)) {
    safe.open();
  }
  kh::SimulatedOperator device;
  kh::SafeDevice safe;
};

/// Whole-cycle µs, over all cycles and over those with contact for some hand.
struct WorldCosts {
  std::vector<double> all, in_contact;
  long failures = 0;
  void add(double us, std::span<const kh::CycleRecord> records) {
    all.push_back(us);
    bool touching = false;
    for (const kh::CycleRecord& r : records) {
      touching = touching || r.contact.statistics.points_in_contact > 0;
      if (!(r.device_valid && r.contact_valid && r.coupling_valid && r.integrators_ok)) ++failures;
    }
    if (touching) in_contact.push_back(us);
  }
};

void print_world_costs(const char* name, const WorldCosts& costs) {
  const Spread all = spread(costs.all), touching = spread(costs.in_contact);
  std::printf(
      "  %-44s mean %7.1f  p99 %7.1f | in contact (%5zu cycles) mean %7.1f  p99 %7.1f"
      "  failed %ld\n",
      name, all.mean, all.p99, costs.in_contact.size(), touching.mean, touching.p99,
      costs.failures);
}

/// The single-object cycle of thesis Figure 4.2 written out from the library's calls, for the held
/// dino against a fixed rigid pointshell: read the device, query at the simulation pose, step the
/// coupling, write the rendered wrench (zero if anything failed). The reference a World of one
/// pair is measured against.
class WrittenOutCycle {
 public:
  WrittenOutCycle(const SceneSpec& spec, kh::SafeDevice& device,
                  const kh::CouplingOptions& coupling)
      : m_tree(*spec.rigid_tree),
        m_placement(spec.placement),
        m_device(device),
        m_coupling(coupling, script_start(spec.placement)),
        m_workspace(*spec.rigid_tree, spec.contact) {}

  const kh::CycleRecord& run(double now) noexcept {
    m_device.begin_cycle(now + period);
    kh::CycleRecord& r = m_record;
    r = kh::CycleRecord{};
    r.time = now;
    r.device_valid = m_device.read(m_state);
    r.manipulandum = m_state.pose;
    kh::Wrench rendered;
    if (r.device_valid) {
      const kh::Pose& grasp = m_coupling.simulation_pose();
      kc::ContactFrames frames;
      frames.pointshell = m_placement.pointshell;
      frames.field = kh::held_body_pose(grasp, m_placement.grasp);
      frames.grasp_point = grasp.position;
      r.contact_valid = kc::query_contact(m_tree, dino_field(), frames, m_workspace);
      if (r.contact_valid) {
        r.contact = m_workspace.result();
        const kh::CouplingStep step = m_coupling.step(m_state.pose, r.contact);
        r.coupling_valid = step.valid;
        if (step.valid) rendered = step.rendered;
      }
    }
    r.simulation = m_coupling.simulation_pose();
    m_device.write(rendered);
    r.rendered = m_device.last_output();
    m_device.end_cycle(now);
    return r;
  }

 private:
  const kc::PointTree& m_tree;
  const Placement& m_placement;
  kh::SafeDevice& m_device;
  kh::VirtualCoupling m_coupling;
  kc::ContactWorkspace m_workspace;
  kh::DeviceState m_state;
  kh::CycleRecord m_record;
};

/// Scene a's pair run two ways in lock step, cycle by cycle (so both see the machine alike):
/// written out from the library's calls (WrittenOutCycle), and by a World of its two bodies; then a
/// World of three bodies and two hands: the held dino, a bunny held by a second hand at its
/// place (still), and a fixed bunny turned to face the dino's other flank.
void run_world(const SceneSpec& spec, int cycles) {
  const Placement& placement = spec.placement;
  const kc::PointTree& bunny = *spec.rigid_tree;
  const kh::DeviceCapabilities capabilities = kh::SimulatedOperator(hand_target()).capabilities();
  const kh::CouplingOptions coupling = coupling_options(spec.contact, placement, capabilities);

  const auto bunny_body = [&](const Eigen::Isometry3d& pose) {
    return rigid_pointshell("bunny", bunny, pose);
  };

  // One pair: written out against World, alternating. Their watchdogs see the simulated clock,
  // so a cycle the machine delays does not zero one's output and not the other's: the two then
  // render the same forces, and any difference is the World's doing. Both couplings start at the
  // script's first anchor.
  OperatorHand reference_hand(hand_target(), placement.grasp);
  WrittenOutCycle reference(spec, reference_hand.safe, coupling);
  OperatorHand one_hand(hand_target(), placement.grasp);
  kh::World one_pair({held_dino(placement), bunny_body(placement.pointshell)},
                     {holding(0, placement.grasp, one_hand.safe, coupling)}, spec.contact);
  WorldCosts cycle_costs, world_costs;
  double largest_difference = 0.0;  // N, between the two ways' contact forces
  for (int i = 0; i < cycles; ++i) {
    const double now = i * period;
    Clock::time_point start = Clock::now();
    const kh::CycleRecord& r = reference.run(now);
    cycle_costs.add(microseconds(Clock::now() - start), std::span(&r, 1));
    start = Clock::now();
    const std::span<const kh::CycleRecord> records =
        one_pair.cycle(now, now + period, [now] { return now; });
    world_costs.add(microseconds(Clock::now() - start), records);
    largest_difference =
        std::max(largest_difference, (records.front().contact.force - r.contact.force).norm());
  }
  std::printf("\nPart 3: the multi-body World (%d cycles each, µs per whole cycle)\n", cycles);
  print_world_costs("one pair, written out from the library's calls", cycle_costs);
  print_world_costs("one pair, World", world_costs);
  std::printf(
      "  World ÷ written out: mean %.3f, p99 %.3f (in contact: mean %.3f, p99 %.3f); "
      "largest force difference %.3g N\n",
      spread(world_costs.all).mean / spread(cycle_costs.all).mean,
      spread(world_costs.all).p99 / spread(cycle_costs.all).p99,
      spread(world_costs.in_contact).mean / spread(cycle_costs.in_contact).mean,
      spread(world_costs.in_contact).p99 / spread(cycle_costs.in_contact).p99, largest_difference);

  // Two hands, three bodies: pairs dino–held bunny (queried once per hand) and dino–fixed bunny.
  // The fixed bunny, turned half a turn about y, touches the dino's other flank where the dino
  // starts (the script starts 3 cm back from the first bunny, towards this one).
  const Eigen::Isometry3d dino_start = kh::held_body_pose(script_start(placement), placement.grasp);
  const auto other_flank = [&](double u) {
    Eigen::Isometry3d pose(Eigen::AngleAxisd(std::numbers::pi, Eigen::Vector3d::UnitY()));
    pose.translation() = Eigen::Vector3d(-u, placement.pointshell.translation().y(), 0.0);
    return pose;
  };
  const Eigen::Isometry3d facing_other_flank =
      dino_start * other_flank(khz::bench::solve_increasing(
                       [&](double u) {
                         return khz::bench::min_distance(khz::bench::RigidShape(bunny),
                                                         dino_field(), other_flank(u));
                       },
                       1.0, 0.25 * voxel(), 1e-3 * voxel()));
  OperatorHand dino_hand(hand_target(), placement.grasp);
  OperatorHand bunny_hand([](double) { return kh::Pose{}; }, placement.grasp);
  kh::World two_hands(
      {held_dino(placement), bunny_body(placement.pointshell), bunny_body(facing_other_flank)},
      {holding(0, placement.grasp, dino_hand.safe, coupling),
       holding(1, placement.pointshell.inverse() * placement.grasp, bunny_hand.safe, coupling)},
      spec.contact);

  WorldCosts three_bodies;
  long both_in_contact = 0;
  for (int i = 0; i < cycles; ++i) {
    const double now = i * period;
    const Clock::time_point start = Clock::now();
    const std::span<const kh::CycleRecord> records =
        two_hands.cycle(now, now + period, [now] { return now; });
    three_bodies.add(microseconds(Clock::now() - start), records);
    both_in_contact += records[0].contact.statistics.points_in_contact > 0 &&
                       records[1].contact.statistics.points_in_contact > 0;
  }
  print_world_costs("two hands, three bodies, 3 queries", three_bodies);
  std::printf("  (both hands in contact in %ld cycles)\n", both_in_contact);
}

int main(int argc, char** argv) {
  CLI::App app{"Haptic loop: full-cycle costs and the 1 kHz loop under load"};
  LoopRunOptions loop;
  int cycles = static_cast<int>(script_seconds / period);
  double budget = 300.0;
  std::string loop_scene = "c";
  bool costs_fifo = false, skip_costs = false, skip_loop = false, skip_world = false;
  app.add_option("--seconds", loop.seconds, "Duration of each real-time loop run (s)")
      ->check(CLI::PositiveNumber);
  app.add_option("--cycles", cycles, "Cycles per scene for the full-cycle costs")
      ->check(CLI::PositiveNumber);
  app.add_option("--budget", budget, "Scene c's contact-query time budget (µs)")
      ->check(CLI::PositiveNumber);
  app.add_option("--loop-scene", loop_scene, "The scene the real-time loop runs")
      ->check(CLI::IsMember({"a", "c"}));
  app.add_option("--load", loop.load, "What loads the other core during the loop")
      ->check(CLI::IsMember({"spin", "memory", "none"}));
  app.add_option("--priority", loop.priority, "SCHED_FIFO priority requested")
      ->check(CLI::Range(1, 99));
  app.add_flag("--costs-fifo", costs_fifo,
               "Run the full-cycle costs on --cpu at SCHED_FIFO (not preempted by others)");
  app.add_option("--cpu", loop.cpu, "The CPU the pinned runs use (the load takes the next one)")
      ->check(CLI::Range(0, static_cast<int>(std::thread::hardware_concurrency()) - 1));
  app.add_flag("--skip-costs", skip_costs, "Skip the full-cycle costs");
  app.add_flag("--skip-loop", skip_loop, "Skip the real-time loop runs");
  app.add_flag("--skip-world", skip_world, "Skip the multi-body World's costs");
  CLI11_PARSE(app, argc, argv);

  const kc::ContactOptions full;
  kc::ContactOptions budgeted;
  budgeted.degradation.mode = kc::DegradationOptions::Mode::time_budget;
  budgeted.degradation.budget_microseconds = budget;
  const std::string budget_name =
      "c bunny 1M, budget " + std::to_string(static_cast<int>(budget)) + " µs";

  std::printf("Precomputes (bench_contact_query's cache: %s)\n", KHZ_CONTACT_CACHE_DIR);
  std::fflush(stdout);
  std::vector<SceneSpec> scenes;
  scenes.push_back(bunny_scene("a rigid bunny 1M", full));
  if (!skip_costs) scenes.push_back(dragon_scene(full));
  scenes.push_back(bunny_scene(budget_name, budgeted));
  for (const auto& p : khz::bench::precompute_log()) {
    std::printf("  %-40s %8.2f s %s\n", p.what.c_str(), p.seconds,
                p.from_cache ? "cache" : "built");
  }
  std::printf("dino 256³ field, voxel h = %.2f mm; k_C %.0f N/m, L %.0f; k_VC 500 N/m\n",
              1e3 * voxel(), full.stiffness, full.scaling_count);

  if (!skip_costs) {
    std::printf("\nPart 1: full-cycle costs%s\n",
                costs_fifo
                    ? (realtime_on_cpu(loop.cpu, loop.priority) ? " (pinned, SCHED_FIFO)"
                                                                : " (SCHED_FIFO or pin refused)")
                    : "");
    std::vector<CostRun> runs;
    for (const SceneSpec& spec : scenes) runs.push_back(run_costs(spec, cycles, costs_fifo));
    print_costs(runs);
    if (costs_fifo) normal_priority();
  }
  if (!skip_world) run_world(scenes.front(), cycles);
  if (!skip_loop) {
    std::printf("\nPart 2: the real-time loop (%u CPUs online)\n",
                std::thread::hardware_concurrency());
    const SceneSpec& spec = loop_scene == "a" ? scenes.front() : scenes.back();
    loop.pinned = true;
    run_loop(spec, loop);
    loop.pinned = false;
    run_loop(spec, loop);
  }
  return 0;
}
