// Per-cycle costs of the contact query (thesis §3.10) in the spirit of Table 3.1: recorded,
// smooth trajectories with shallow distributed contact, one query per haptic cycle, on one core.
//
// A  rigid–rigid, large: bunny00.off as a 1.02M-point, 6-level repulsion pointshell against
//    dino.off's 256³ signed field: approach, slide, rotate, leave at 0.3–0.9 voxel penetration.
// B  deformable–rigid: ChineseDragon-10kv.off as a 262k-point, 5-level pointshell (on the offset
//    surface of its polygon-soup field) embedded in a voxel mesh with an r = 15 modal-derivative
//    basis, q following a scripted deformation, against dino.off's 256³ field.
// C  peg in hole (Fig. 3.28): a block with a blind square hole (256³ field) and a square peg
//    (262k points, 5 levels) a little wider than the hole, lowered into it slightly turned and
//    off-centre, so most of its walls touch: full traversal, and time-budget degradation
//    (§3.10.3) at 100 and 250 µs.
// E  deformable–deformable (Table 3.1's dragon + dinosaur): B's dragon and path against the dino
//    deforming too (r = 15), through its deformed distance field (§3.12: 40 proxies, k = 5).
// F  peg edge on wall: C's block and a peg 4 mm narrower than the hole on each side, tilted 5°
//    and pressed against one wall so that only its lowest edge digs in, as in an assembly
//    insertion; lowered, rocked and pulled up as in C.
// D  graceful degradation's force error: force and torque rendering levels 0…L−1 only, against
//    the full depth, at contact poses of A and C.
//
// Each run plays its trajectory three times (the first to warm caches; reset() before each),
// and reports per query: µs (mean, p50, p99, max), nodes traversed and skipped, points in
// contact, the deepest level and ns per traversed node (total time / total nodes), with and
// without temporal coherence (§3.10.2, bounds measured from the trajectory), and with Coulomb
// friction (FrictionOptions; its cost per query and per point in contact against none). The tables
// at the end collect every run. Precomputes are cached in KHZ_CONTACT_CACHE_DIR (first run:
// minutes; later runs: seconds).
//
// Scene<Tree, Field> and run_scene() take any DistanceField; a scene's `prepare` deforms a
// deformable field object before each query.
#include "contact_scenes.hpp"

#include <khz/contact/field/deformed_distance_field.hpp>
#include <khz/contact/query/contact_query.hpp>

#include <benchmark/benchmark.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <map>
#include <memory>
#include <numbers>
#include <string>
#include <type_traits>
#include <vector>

namespace {

namespace kc = khz::contact;
namespace kr = khz::reduced;
using khz::bench::Clock;
using khz::bench::degrees;
using khz::bench::quantile;
using khz::bench::ramp;
using khz::bench::rotation_about;
using khz::bench::Trajectory;
using khz::bench::TrajectoryScript;

// ---------------------------------------------------------------------------------------------
// Scenes.

/// What a configuration runs: a pointshell tree (PointTree or DeformablePointTree) against a
/// field object satisfying DistanceField, along a trajectory.
template <typename Tree, kc::DistanceField Field>
struct Scene {
  std::string name;
  const Tree* tree = nullptr;
  const Field* field = nullptr;
  std::string field_label;  // e.g. "256³"
  double voxel = 0.0;       // the field's spacing (m)
  Trajectory trajectory;
  kc::CoherenceOptions coherence;  // bounds the trajectory keeps
  /// r of a deformable field object (0: rigid), and what brings it to pose i's deformation
  /// before that pose's query (timed with it: it is part of the haptic cycle).
  Eigen::Index field_dimension = 0;
  std::function<bool(std::size_t)> prepare;

  const kc::PointTree& point_tree() const {
    if constexpr (std::is_same_v<Tree, kc::DeformablePointTree>) {
      return tree->tree();
    } else {
      return *tree;
    }
  }
};

const kc::DistanceGrid& dino_field() {
  static const kc::DistanceGrid field =
      khz::bench::cached_signed_field("dino", khz::bench::demo_mesh("dino.off", 1.0), 256);
  return field;
}

std::string cube_label(const kc::DistanceGrid& grid) {
  return std::to_string(grid.geometry().cells) + "³";
}

// A and B: a pointshell against the dino's 256³ field, along its flank.
template <typename Tree>
Scene<Tree, kc::DistanceGrid> dino_scene(const std::string& name, const Tree& tree) {
  Scene<Tree, kc::DistanceGrid> s;
  s.name = name;
  s.tree = &tree;
  s.field = &dino_field();
  s.field_label = cube_label(dino_field());
  s.voxel = dino_field().geometry().spacing;
  return s;
}

/// Rubbing the dino's flank from +x: approach to contact (s ≤ 0.15), slide `slide` (m) along z
/// at height y_centre ± 30 mm (to 0.45), turn `turn_degrees` about the approach axis (to 0.75)
/// while rocking ±12° about z, slide back 40% and leave (from 0.8). In contact the deepest
/// point stays 0.3–0.9 voxel h deep (the haptic loop's saturation, §3.13).
TrajectoryScript flank_script(double h, double turn_degrees, double y_centre, double slide) {
  TrajectoryScript script;
  script.rotation = [turn_degrees](double t) {
    return Eigen::Matrix3d(
        rotation_about(Eigen::Vector3d::UnitX(), turn_degrees * degrees * ramp(t, 0.45, 0.75)) *
        rotation_about(Eigen::Vector3d::UnitZ(),
                       12.0 * degrees * std::sin(3.0 * std::numbers::pi * t)));
  };
  script.lateral = [y_centre, slide](double t) {
    return Eigen::Vector3d(0.0, y_centre + 0.03 * std::sin(2.0 * std::numbers::pi * t),
                           slide * (-0.5 + ramp(t, 0.15, 0.45) - 0.4 * ramp(t, 0.6, 0.9)));
  };
  script.clearance = [h](double t) {
    return 0.03 * (1.0 - ramp(t, 0.0, 0.12)) + 0.03 * ramp(t, 0.85, 1.0) -
           h * (0.6 + 0.3 * std::sin(6.0 * std::numbers::pi * t)) *
               (ramp(t, 0.08, 0.15) - ramp(t, 0.8, 0.87));
  };
  return script;
}

// A: bunny (0.5 m) against the dino (1 m) from +x: approach, slide along the flank, turn 60°
// about the approach axis with a rocking tilt, leave.
const Scene<kc::PointTree, kc::DistanceGrid>& scene_a() {
  static const auto scene = [] {
    static const kc::PointTree tree(khz::bench::cached_pointshell(
        "bunny", khz::bench::demo_mesh("bunny00.off", 0.5), false, 256, 750, 6));
    auto s = dino_scene("A rigid bunny/dino", tree);
    const double h = s.voxel;
    const TrajectoryScript script = flank_script(h, 60.0, 0.05, 0.24);
    const Clock::time_point start = Clock::now();
    s.trajectory = khz::bench::record_trajectory(
        script, [&](const Eigen::VectorXd&) { return khz::bench::RigidShape(tree); }, *s.field, h);
    khz::bench::precompute_log().push_back(
        {"A trajectory", khz::bench::seconds_since(start), false});
    s.coherence = khz::bench::coherence_bounds(s.trajectory, tree, 0.0);
    return s;
  }();
  return scene;
}

/// q(t) of a scripted deformation: each coordinate a sine of 1–3 periods over the trajectory.
Eigen::VectorXd scripted_q(Eigen::Index r, double t) {
  Eigen::VectorXd q(r);
  for (Eigen::Index j = 0; j < r; ++j) {
    const double periods = 1.0 + static_cast<double>(j % 3);
    q[j] = std::sin(2.0 * std::numbers::pi * periods * t + 0.7 * static_cast<double>(j)) /
           (1.0 + 0.3 * static_cast<double>(j));
  }
  return q;
}

/// The factor that makes scripted_q()'s largest vertex displacement `size` (m) over t ∈ [0, 1].
double scripted_amplitude(const kr::Basis& basis, double size) {
  double largest = 0.0;
  for (int k = 0; k <= 100; ++k) {
    const Eigen::VectorXd u = basis.vectors * scripted_q(basis.vectors.cols(), k / 100.0);
    for (Eigen::Index v = 0; 3 * v < u.size(); ++v)
      largest = std::max(largest, u.segment<3>(3 * v).norm());
  }
  return size / largest;
}

// B: the dragon (0.5 m) bending and twisting with r = 15 while it rubs the dino's flank.
const Scene<kc::DeformablePointTree, kc::DistanceGrid>& scene_b() {
  static const auto scene = [] {
    const kc::TriangleMesh dragon = khz::bench::demo_mesh("ChineseDragon-10kv.off", 0.5);
    const kr::VolumeMesh volume = khz::bench::voxel_volume(dragon);
    const std::vector<int> anchors = khz::bench::lowest_vertices(volume);
    const kr::Basis basis = khz::bench::cached_basis("dragon_voxel32", volume, anchors, 15);
    static const kc::DeformablePointTree tree = khz::bench::cached_deformable_tree(
        "dragon_262229_L5_voxel32_r15",
        [&] { return khz::bench::cached_pointshell("dragon", dragon, true, 256, 769, 5); }, volume,
        basis);

    // q(t) scaled so the largest vertex displacement is about 8% of the dragon's size (40 mm).
    const Eigen::Index r = tree.dimension();
    const double amplitude = scripted_amplitude(basis, 0.04);
    auto s = dino_scene("B deformable dragon r=15/dino", tree);
    const double h = s.voxel;
    TrajectoryScript script = flank_script(h, 40.0, 0.0, 0.2);
    script.q = [r, amplitude](double t) { return Eigen::VectorXd(amplitude * scripted_q(r, t)); };
    const Clock::time_point start = Clock::now();
    s.trajectory = khz::bench::record_trajectory(
        script, [&](const Eigen::VectorXd& q) { return khz::bench::DeformedShape(tree, q); },
        *s.field, h);
    khz::bench::precompute_log().push_back(
        {"B trajectory", khz::bench::seconds_since(start), false});
    s.coherence =
        khz::bench::coherence_bounds(s.trajectory, tree.tree(), tree.displacement_bound());
    std::printf("  B: %ld hexahedra, %ld anchors, r = %ld, largest displacement 40 mm\n",
                static_cast<long>(volume.num_elements()), static_cast<long>(anchors.size()),
                static_cast<long>(r));
    return s;
  }();
  return scene;
}

// E: B's dragon and path against the dino deforming too (r = 15, a voxel model anchored at its
// lowest 8%, its largest displacement 6 mm, about one voxel): the deformed distance field of
// §3.12 with 40 proxies on dino.off's 256³ rest field (Table 3.1's dragon(d) + dinosaur(d)).
// The path was recorded against the rest field. Temporal coherence bounds the dino's surface
// motion by max_v ‖U_v‖·‖Δq‖; the forces with and without it are compared (the proxy blend is
// an approximation that bound does not strictly cover).
const Scene<kc::DeformablePointTree, kc::DeformedFieldState>& scene_e() {
  static const auto scene = [] {
    const auto& b = scene_b();
    const kr::VolumeMesh volume = khz::bench::voxel_volume(khz::bench::demo_mesh("dino.off", 1.0));
    const kr::Basis basis =
        khz::bench::cached_basis("dino_voxel32", volume, khz::bench::lowest_vertices(volume), 15);
    const Clock::time_point start = Clock::now();
    static const kc::DeformedDistanceField deformed({dino_field()}, kr::MeshEmbedding(volume),
                                                    basis.vectors);
    khz::bench::precompute_log().push_back(
        {"dino proxies and modes", khz::bench::seconds_since(start), false});
    static kc::DeformedFieldState state(deformed);
    const double amplitude = scripted_amplitude(basis, 0.006);
    auto field_q = std::make_shared<std::vector<Eigen::VectorXd>>();
    for (std::size_t i = 0; i < b.trajectory.size(); ++i) {
      const double t = static_cast<double>(i) / static_cast<double>(b.trajectory.size() - 1);
      field_q->push_back(amplitude * scripted_q(basis.vectors.cols(), 1.0 - t));
    }
    Scene<kc::DeformablePointTree, kc::DeformedFieldState> s;
    s.name = "E dragon r=15/dino r=15";
    s.tree = b.tree;
    s.field = &state;
    s.field_label = cube_label(dino_field());
    s.voxel = b.voxel;
    s.trajectory = b.trajectory;
    s.field_dimension = deformed.dimension();
    s.prepare = [field_q](std::size_t i) { return state.update((*field_q)[i]); };
    s.coherence = b.coherence;
    for (std::size_t i = 1; i < field_q->size(); ++i) {
      s.coherence.max_field_deformation = std::max(
          s.coherence.max_field_deformation,
          1.02 * deformed.displacement_bound() * ((*field_q)[i] - (*field_q)[i - 1]).norm());
    }
    return s;
  }();
  return scene;
}

// C and F's block: 200 × 200 × 120 mm (top at z = 0.12 m) with an 80 × 80 × 100 mm blind hole.
constexpr double block_top = 0.12;
const kc::DistanceGrid& block_field() {
  static const kc::DistanceGrid field = khz::bench::cached_signed_field(
      "block_with_hole", khz::bench::block_with_hole(0.1, block_top, 0.04, 0.1), 256);
  return field;
}

// A peg scene on the block: 400 poses lowering the peg from 20 mm above the block to 85 mm
// deep, rocking it (`rock` is the rocking's phase, 0 outside it) and pulling it up to 30 mm.
// `pose_at(bottom, rock)` turns and places the peg whose bottom is at height `bottom` (m).
using PegPose = std::function<Eigen::Isometry3d(double bottom, double rock)>;
Scene<kc::PointTree, kc::DistanceGrid> peg_scene(const std::string& name, const kc::PointTree& tree,
                                                 const PegPose& pose_at) {
  const kc::DistanceGrid& field = block_field();
  Scene<kc::PointTree, kc::DistanceGrid> s;
  s.name = name;
  s.tree = &tree;
  s.field = &field;
  s.field_label = cube_label(field);
  s.voxel = field.geometry().spacing;
  const int poses = 400;
  const Clock::time_point start = Clock::now();
  for (int i = 0; i < poses; ++i) {
    const double t = static_cast<double>(i) / (poses - 1);
    const double bottom = block_top + 0.02 - 0.105 * ramp(t, 0.0, 0.7) + 0.055 * ramp(t, 0.85, 1.0);
    const Eigen::Isometry3d pose =
        pose_at(bottom, std::sin(4.0 * std::numbers::pi * ramp(t, 0.7, 0.85)));
    s.trajectory.pointshell.push_back(pose);
    s.trajectory.penetration.push_back(
        std::max(0.0, -khz::bench::min_distance(khz::bench::RigidShape(tree), field, pose)));
  }
  khz::bench::precompute_log().push_back(
      {name + " trajectory", khz::bench::seconds_since(start), false});
  s.coherence = khz::bench::coherence_bounds(s.trajectory, tree, 0.0);
  return s;
}

// C: the peg is 0.8 voxel wider than the hole, turned 0.4° about the vertical, 0.3 voxel
// off-centre, and rocked by 0.05° about x.
const Scene<kc::PointTree, kc::DistanceGrid>& scene_c() {
  static const auto scene = [] {
    const double h = block_field().geometry().spacing;
    static const kc::PointTree tree(khz::bench::cached_pointshell(
        "peg", khz::bench::square_peg(0.04 + 0.4 * h, 0.14), false, 128, 769, 5));
    return peg_scene("C peg in hole", tree, [h](double bottom, double rock) {
      Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
      pose.linear() = rotation_about(Eigen::Vector3d::UnitZ(), 0.4 * degrees) *
                      rotation_about(Eigen::Vector3d::UnitX(), 0.05 * degrees * rock);
      pose.translation() = Eigen::Vector3d(0.3 * h, 0.0, bottom);
      return pose;
    });
  }();
  return scene;
}

// F: a peg 4 mm narrower than the hole on each side, tilted 5° about y, pressed against the
// hole's +x wall so that only its lowest edge digs in (0.5 voxel, a strip a few mm tall): the
// usual contact of an assembly insertion. Rocked by 0.3° about x.
const Scene<kc::PointTree, kc::DistanceGrid>& scene_f() {
  static const auto scene = [] {
    const double half_hole = 0.04, clearance = 0.004, tilt = 5.0 * degrees;
    const double h = block_field().geometry().spacing;
    const double half_peg = half_hole - clearance;
    static const kc::PointTree tree(khz::bench::cached_pointshell(
        "narrow_peg", khz::bench::square_peg(half_peg, 0.14), false, 128, 769, 5));
    // Turned by −tilt about y, the peg's lowest +x edge is its rightmost line, at
    // x = a cos(tilt) plus the translation.
    const double x = half_hole + 0.5 * h - half_peg * std::cos(tilt);
    return peg_scene("F peg edge on wall", tree, [x, tilt](double bottom, double rock) {
      Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
      pose.linear() = rotation_about(Eigen::Vector3d::UnitX(), 0.3 * degrees * rock) *
                      rotation_about(Eigen::Vector3d::UnitY(), -tilt);
      pose.translation() = Eigen::Vector3d(x, 0.0, bottom);
      return pose;
    });
  }();
  return scene;
}

// ---------------------------------------------------------------------------------------------
// Running a scene.

template <typename Tree, kc::DistanceField Field>
bool query(const Scene<Tree, Field>& scene, std::size_t pose, kc::ContactWorkspace& workspace) {
  if (scene.prepare && !scene.prepare(pose)) return false;
  kc::ContactFrames frames;
  frames.pointshell = scene.trajectory.pointshell[pose];
  if constexpr (std::is_same_v<Tree, kc::DeformablePointTree>) {
    return kc::query_contact(*scene.tree, scene.trajectory.q[pose], *scene.field, frames,
                             workspace);
  } else {
    return kc::query_contact(*scene.tree, *scene.field, frames, workspace);
  }
}

double mean(const std::vector<double>& values) {
  double sum = 0.0;
  for (const double v : values) sum += v;
  return values.empty() ? 0.0 : sum / static_cast<double>(values.size());
}

double largest(const std::vector<double>& values) {
  return values.empty() ? 0.0 : *std::max_element(values.begin(), values.end());
}

struct RunSummary {
  std::string scene, variant;
  Eigen::Index points = 0;
  int levels = 0;
  std::string field;
  double penetration_voxels = 0.0;  // deepest over the trajectory
  double contact_share = 0.0;       // of the queries with a point in contact
  double us_mean = 0, us_p50 = 0, us_p99 = 0, us_max = 0;
  double nodes_mean = 0, nodes_max = 0, skipped_mean = 0;
  double contacts_mean = 0, contacts_max = 0;
  int deepest_max = 0;
  double ns_per_node = 0.0;
  double budget_us = 0.0;               // time_budget runs
  double within_budget = 0.0;           // share of queries within it
  std::map<int, int> deepest_levels;    // level → queries
  long coherence_drops = 0;             // TC runs: queries that dropped their skips
  std::vector<Eigen::Vector3d> forces;  // per query of the last pass
};

std::vector<RunSummary>& summaries() {
  static std::vector<RunSummary> all;
  return all;
}

/// Plays the scene's trajectory three times with `options` (reset() before each pass, the first
/// pass not measured), one query per pose.
template <typename Tree, kc::DistanceField Field>
RunSummary run_scene(const Scene<Tree, Field>& scene, const kc::ContactOptions& options,
                     const std::string& variant) {
  kc::ContactWorkspace workspace(*scene.tree, options, scene.field_dimension);
  std::vector<double> us, nodes, skipped, contacts;
  RunSummary summary;
  double total_seconds = 0.0, total_nodes = 0.0;
  std::string csv = "pass,pose,us,nodes,skipped,contacts,deepest,penetration_voxels\n";
  for (int pass = 0; pass < 3; ++pass) {
    workspace.reset();
    for (std::size_t i = 0; i < scene.trajectory.size(); ++i) {
      const Clock::time_point start = Clock::now();
      const bool ok = query(scene, i, workspace);
      const double seconds = khz::bench::seconds_since(start);
      if (!ok) throw kc::Error(scene.name + ": query refused at pose " + std::to_string(i));
      const kc::ContactStatistics& stats = workspace.result().statistics;
      if (pass == 0) continue;
      csv += std::to_string(pass) + "," + std::to_string(i) + "," + std::to_string(1e6 * seconds) +
             "," + std::to_string(stats.nodes_traversed) + "," +
             std::to_string(stats.nodes_skipped) + "," + std::to_string(stats.points_in_contact) +
             "," + std::to_string(stats.deepest_level) + "," +
             std::to_string(scene.trajectory.penetration[i] / scene.voxel) + "\n";
      us.push_back(1e6 * seconds);
      nodes.push_back(static_cast<double>(stats.nodes_traversed));
      skipped.push_back(static_cast<double>(stats.nodes_skipped));
      contacts.push_back(static_cast<double>(stats.points_in_contact));
      total_seconds += seconds;
      total_nodes += static_cast<double>(stats.nodes_traversed);
      ++summary.deepest_levels[stats.deepest_level];
      summary.deepest_max = std::max(summary.deepest_max, stats.deepest_level);
      if (stats.coherence_reset) ++summary.coherence_drops;
      if (pass == 2) summary.forces.push_back(workspace.result().force);
      if (options.degradation.mode == kc::DegradationOptions::Mode::time_budget &&
          1e6 * seconds <= options.degradation.budget_microseconds) {
        summary.within_budget += 1.0;
      }
      if (stats.points_in_contact > 0) summary.contact_share += 1.0;
    }
  }
  // Per-query rows, to plot time against nodes.
  khz::bench::write_run_csv("contact_query_runs", scene.name + ", " + variant, csv);
  const kc::PointTree& tree = scene.point_tree();
  summary.scene = scene.name;
  summary.variant = variant;
  summary.points = tree.num_points();
  summary.levels = tree.num_levels();
  summary.field = scene.field_label;
  summary.penetration_voxels = largest(scene.trajectory.penetration) / scene.voxel;
  const auto queries = static_cast<double>(us.size());
  summary.contact_share /= queries;
  summary.within_budget /= queries;
  summary.budget_us = options.degradation.mode == kc::DegradationOptions::Mode::time_budget
                          ? options.degradation.budget_microseconds
                          : 0.0;
  summary.us_mean = mean(us);
  summary.us_p50 = quantile(us, 0.5);
  summary.us_p99 = quantile(us, 0.99);
  summary.us_max = largest(us);
  summary.nodes_mean = mean(nodes);
  summary.nodes_max = largest(nodes);
  summary.skipped_mean = mean(skipped);
  summary.contacts_mean = mean(contacts);
  summary.contacts_max = largest(contacts);
  summary.ns_per_node = total_nodes > 0.0 ? 1e9 * total_seconds / total_nodes : 0.0;
  return summary;
}

kc::ContactOptions full_traversal(bool coherent, const kc::CoherenceOptions& bounds) {
  kc::ContactOptions options;
  if (coherent) options.coherence = bounds;
  return options;
}

/// The friction the "full, friction" runs add (FrictionOptions): μ_s 0.5, μ_k 0.4, so points
/// both stick and slide along the recorded slides.
kc::ContactOptions with_friction() {
  kc::ContactOptions options;
  options.friction.static_coefficient = 0.5;
  options.friction.kinetic_coefficient = 0.4;
  return options;
}

void report(benchmark::State& state, const RunSummary& s) {
  state.SetIterationTime(1e-6 * s.us_mean);
  state.counters["points"] = static_cast<double>(s.points);
  state.counters["levels"] = s.levels;
  state.counters["us_p99"] = s.us_p99;
  state.counters["us_max"] = s.us_max;
  state.counters["nodes"] = s.nodes_mean;
  state.counters["skipped"] = s.skipped_mean;
  state.counters["contacts"] = s.contacts_mean;
  state.counters["deepest"] = s.deepest_max;
  state.counters["ns_per_node"] = s.ns_per_node;
  if (s.budget_us > 0.0) state.counters["within_budget"] = s.within_budget;
}

template <typename SceneGetter>
void register_runs(const std::string& prefix, SceneGetter get, bool with_budgets) {
  for (const bool coherent : {false, true}) {
    const std::string variant = coherent ? "full, TC" : "full";
    benchmark::RegisterBenchmark(
        (prefix + (coherent ? "/full/coherence" : "/full")).c_str(),
        [get, coherent, variant](benchmark::State& state) {
          const auto& scene = get();
          for (auto _ : state) {
            summaries().push_back(
                run_scene(scene, full_traversal(coherent, scene.coherence), variant));
            report(state, summaries().back());
          }
        })
        ->Iterations(1)
        ->UseManualTime()
        ->Unit(benchmark::kMicrosecond);
  }
  benchmark::RegisterBenchmark(
      (prefix + "/full/friction").c_str(),
      [get](benchmark::State& state) {
        const auto& scene = get();
        for (auto _ : state) {
          summaries().push_back(run_scene(scene, with_friction(), "full, friction"));
          report(state, summaries().back());
        }
      })
      ->Iterations(1)
      ->UseManualTime()
      ->Unit(benchmark::kMicrosecond);
  if (!with_budgets) return;
  for (const double budget : {100.0, 250.0}) {
    const std::string variant = "budget " + std::to_string(static_cast<int>(budget)) + " µs";
    benchmark::RegisterBenchmark(
        (prefix + "/budget_us:" + std::to_string(static_cast<int>(budget))).c_str(),
        [get, budget, variant](benchmark::State& state) {
          const auto& scene = get();
          kc::ContactOptions options;
          options.degradation.mode = kc::DegradationOptions::Mode::time_budget;
          options.degradation.budget_microseconds = budget;
          for (auto _ : state) {
            summaries().push_back(run_scene(scene, options, variant));
            report(state, summaries().back());
          }
        })
        ->Iterations(1)
        ->UseManualTime()
        ->Unit(benchmark::kMicrosecond);
  }
}

// ---------------------------------------------------------------------------------------------
// D: force error per level.

struct LevelErrors {
  std::string scene;
  std::size_t pose = 0;
  long contacts = 0;                              // full depth
  double force = 0.0;                             // |F| full depth (N)
  std::vector<double> force_error, torque_error;  // per max_level, relative
};

std::vector<LevelErrors>& level_errors() {
  static std::vector<LevelErrors> all;
  return all;
}

/// At the poses with the most points in contact, the 75th and the 50th percentile of the contact
/// poses: the force and torque with max_level = 0 … L−1 against the full depth.
template <typename Tree, kc::DistanceField Field>
void force_error_per_level(const Scene<Tree, Field>& scene) {
  kc::ContactWorkspace workspace(*scene.tree, kc::ContactOptions{}, scene.field_dimension);
  std::vector<std::pair<long, std::size_t>> by_contacts;
  for (std::size_t i = 0; i < scene.trajectory.size(); ++i) {
    query(scene, i, workspace);
    const long c = static_cast<long>(workspace.result().statistics.points_in_contact);
    if (c > 0) by_contacts.emplace_back(c, i);
  }
  std::sort(by_contacts.begin(), by_contacts.end());
  if (by_contacts.empty()) return;
  const int levels = scene.point_tree().num_levels();
  for (const double fraction : {1.0, 0.75, 0.5}) {
    const auto& [contacts, pose] = by_contacts[static_cast<std::size_t>(
        fraction * static_cast<double>(by_contacts.size() - 1))];
    kc::ContactOptions options;
    workspace.set_options(options);
    query(scene, pose, workspace);
    const Eigen::Vector3d force = workspace.result().force;
    const Eigen::Vector3d torque = workspace.result().torque;
    LevelErrors row{scene.name, pose, contacts, force.norm(), {}, {}};
    for (int level = 0; level < levels; ++level) {
      options.max_level = level;
      workspace.set_options(options);
      query(scene, pose, workspace);
      row.force_error.push_back((workspace.result().force - force).norm() / force.norm());
      row.torque_error.push_back((workspace.result().torque - torque).norm() / torque.norm());
    }
    level_errors().push_back(row);
  }
}

// ---------------------------------------------------------------------------------------------
// Tables.

void print_tables() {
  std::printf("\nPrecomputes (s; 'cache' = read back from KHZ_CONTACT_CACHE_DIR):\n");
  for (const auto& p : khz::bench::precompute_log()) {
    std::printf("  %-40s %8.2f %s\n", p.what.c_str(), p.seconds, p.from_cache ? "cache" : "built");
  }
  std::printf(
      "\nPer query, one core, over two passes of each trajectory (TC = temporal coherence):\n");
  std::printf("%-29s %-13s %8s %2s %5s %5s %5s %8s %8s %8s %8s %9s %9s %9s %8s %8s %2s %7s %6s\n",
              "scene", "variant", "points", "L", "field", "pen/h", "cont%", "us mean", "us p50",
              "us p99", "us max", "nodes", "nodes max", "skipped", "contacts", "cont max", "LD",
              "ns/node", "TCdrop");
  for (const RunSummary& s : summaries()) {
    std::printf(
        "%-29s %-13s %8ld %2d %5s %5.2f %5.1f %8.1f %8.1f %8.1f %8.1f %9.0f %9.0f %9.0f %8.0f "
        "%8.0f %2d %7.1f %6ld\n",
        s.scene.c_str(), s.variant.c_str(), static_cast<long>(s.points), s.levels, s.field.c_str(),
        s.penetration_voxels, 100.0 * s.contact_share, s.us_mean, s.us_p50, s.us_p99, s.us_max,
        s.nodes_mean, s.nodes_max, s.skipped_mean, s.contacts_mean, s.contacts_max, s.deepest_max,
        s.ns_per_node, s.coherence_drops);
  }
  std::printf("\nTemporal coherence against full traversal: queries whose force differs\n");
  for (const RunSummary& with : summaries()) {
    if (with.variant != "full, TC") continue;
    for (const RunSummary& without : summaries()) {
      if (without.scene != with.scene || without.variant != "full") continue;
      int differing = 0;
      double worst = 0.0;
      for (std::size_t i = 0; i < with.forces.size() && i < without.forces.size(); ++i) {
        const double difference = (with.forces[i] - without.forces[i]).norm();
        if (difference > 0.0) ++differing;
        if (without.forces[i].norm() > 0.0) {
          worst = std::max(worst, difference / without.forces[i].norm());
        }
      }
      std::printf("  %-29s %d of %zu queries, largest relative difference %.2e\n",
                  with.scene.c_str(), differing, with.forces.size(), worst);
    }
  }
  std::printf(
      "\nFriction (μ_s 0.5, μ_k 0.4) against none, same poses: per query, and per point in "
      "contact\n");
  for (const RunSummary& with : summaries()) {
    if (with.variant != "full, friction") continue;
    for (const RunSummary& without : summaries()) {
      if (without.scene != with.scene || without.variant != "full") continue;
      const double extra_ns = 1e3 * (with.us_mean - without.us_mean);
      std::printf(
          "  %-29s mean %7.1f / %7.1f us = %5.3f, p99 %7.1f / %7.1f us = %5.3f; %+6.1f ns per "
          "point in contact (%.0f points)\n",
          with.scene.c_str(), with.us_mean, without.us_mean, with.us_mean / without.us_mean,
          with.us_p99, without.us_p99, with.us_p99 / without.us_p99,
          with.contacts_mean > 0.0 ? extra_ns / with.contacts_mean : 0.0, with.contacts_mean);
    }
  }
  std::printf(
      "\nTime-budget degradation (§3.10.3): query time against the budget, deepest level\n");
  for (const RunSummary& s : summaries()) {
    if (s.budget_us <= 0.0) continue;
    std::printf("  %-20s %-14s p50 %7.1f  p99 %7.1f  max %7.1f us; within budget %5.1f%%; levels:",
                s.scene.c_str(), s.variant.c_str(), s.us_p50, s.us_p99, s.us_max,
                100.0 * s.within_budget);
    for (const auto& [level, count] : s.deepest_levels) std::printf(" L%d×%d", level, count);
    std::printf("\n");
  }
  if (!level_errors().empty()) {
    std::printf("\nForce / torque error rendering levels 0…i only, relative to the full depth:\n");
    for (const LevelErrors& row : level_errors()) {
      std::printf("  %-20s pose %3zu (%6ld contacts, |F| %8.3g N):", row.scene.c_str(), row.pose,
                  row.contacts, row.force);
      for (std::size_t level = 0; level < row.force_error.size(); ++level) {
        std::printf("  L%zu %5.1f%%/%5.1f%%", level, 100.0 * row.force_error[level],
                    100.0 * row.torque_error[level]);
      }
      std::printf("\n");
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  // Precomputes on two threads (the machine's two cores); the queries are single-threaded.
  omp_set_num_threads(2);
  register_runs("A_rigid_bunny1M_dino256", scene_a, false);
  register_runs("B_deformable_dragon_r15_dino256", scene_b, false);
  register_runs("C_peg_in_hole", scene_c, true);
  register_runs("E_deformable_dragon_r15_deformable_dino_r15", scene_e, false);
  register_runs("F_peg_edge_on_wall", scene_f, false);
  benchmark::RegisterBenchmark("D_force_error_per_level", [](benchmark::State& state) {
    for (auto _ : state) {
      force_error_per_level(scene_a());
      force_error_per_level(scene_c());
    }
  })->Iterations(1);
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  print_tables();
  return 0;
}
