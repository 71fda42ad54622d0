#include <khz/scene/contact_sweep.hpp>

#include <khz/reduced/stage_progress.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <tuple>

namespace khz::scene {
namespace {

/// The scene's free objects (dynamic World bodies), in its order.
std::vector<int> free_objects(const SceneRuntime& runtime) {
  std::vector<int> objects;
  for (int i = 0; i < static_cast<int>(runtime.description().objects.size()); ++i) {
    if (runtime.world().motion(i) != nullptr) objects.push_back(i);
  }
  return objects;
}

}  // namespace

RecordedState record_state(const SceneRuntime& runtime) {
  RecordedState state;
  for (const haptic::CycleRecord& record : runtime.world().records()) {
    state.grasps.push_back(record.simulation);
  }
  for (int i = 0; i < static_cast<int>(runtime.description().objects.size()); ++i) {
    state.coordinates.push_back(runtime.coordinates(i));
  }
  for (const int i : free_objects(runtime)) state.free_poses.push_back(runtime.pose(i));
  return state;
}

int tree_levels(const PreparedScene& prepared) noexcept {
  int levels = 1;
  for (const PreparedObject& object : prepared.objects) {
    if (object.tree) levels = std::max(levels, object.tree->num_levels());
    if (object.deformable_tree) {
      levels = std::max(levels, object.deformable_tree->tree().num_levels());
    }
  }
  return levels;
}

std::vector<SweepSetting> default_sweep(const contact::ContactOptions& scene_options, int levels) {
  contact::ContactOptions base = scene_options;
  base.coherence.enabled = false;
  base.max_level = -1;
  base.degradation.mode = contact::DegradationOptions::Mode::none;
  std::vector<SweepSetting> settings{{"all levels (reference)", base}};
  for (int level = 0; level + 1 < levels; ++level) {
    contact::ContactOptions fixed = base;
    fixed.max_level = level;
    settings.push_back({"level " + std::to_string(level), fixed});
  }
  for (const double budget : {50.0, 100.0, 250.0}) {
    contact::ContactOptions timed = base;
    timed.degradation = scene_options.degradation;
    timed.degradation.mode = contact::DegradationOptions::Mode::time_budget;
    timed.degradation.budget_microseconds = budget;
    settings.push_back({"budget " + std::to_string(static_cast<int>(budget)) + " us", timed});
  }
  return settings;
}

namespace {

void apply(SceneRuntime& runtime, const RecordedState& state, const std::vector<int>& free) {
  for (std::size_t i = 0; i < state.coordinates.size(); ++i) {
    if (state.coordinates[i].size() > 0)
      runtime.set_coordinates(static_cast<int>(i), state.coordinates[i]);
  }
  for (std::size_t k = 0; k < free.size() && k < state.free_poses.size(); ++k) {
    runtime.world().place_free_body(free[k], state.free_poses[k]);
  }
}

struct Replay {
  std::vector<Eigen::Vector3d> force, torque;
  std::vector<double> us, nodes;
};

constexpr double nan = std::numeric_limits<double>::quiet_NaN();

/// Every state's force and torque per hand, then per free object (state-major), cost and
/// nodes over all pairs; `stage` reports one unit a state.
Replay replay(SceneRuntime& runtime, const std::vector<const RecordedState*>& states,
              const contact::ContactOptions& options, reduced::StageProgress& stage) {
  haptic::World& world = runtime.world();
  world.set_contact_options(options);
  const std::vector<int> free = free_objects(runtime);
  Replay r;
  for (const RecordedState* state : states) {
    apply(runtime, *state, free);
    const bool ok = world.probe(state->grasps);
    contact::ContactStatistics statistics;
    const auto add = [&](const contact::ContactWrench& wrench) {
      r.force.push_back(ok ? wrench.force : Eigen::Vector3d::Constant(nan));
      r.torque.push_back(ok ? wrench.torque : Eigen::Vector3d::Constant(nan));
      statistics.accumulate(wrench.statistics);
    };
    for (int h = 0; h < world.hand_count(); ++h) add(world.wrench(h));
    for (const int i : free) add(world.body_wrench(i));
    r.us.push_back(ok ? statistics.microseconds : nan);
    r.nodes.push_back(ok ? static_cast<double>(statistics.nodes_traversed) : nan);
    stage.advance();
  }
  stage.finish();
  return r;
}

/// RMS |a − b| / RMS |b|, and max |a − b| / max |b| (0 when b is all zero).
std::pair<double, double> relative_errors(const std::vector<Eigen::Vector3d>& a,
                                          const std::vector<Eigen::Vector3d>& b) {
  double difference = 0.0, reference = 0.0, max_difference = 0.0, max_reference = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const double d = (a[i] - b[i]).norm();
    difference += d * d;
    reference += b[i].squaredNorm();
    max_difference = std::max(max_difference, d);
    max_reference = std::max(max_reference, b[i].norm());
  }
  if (!(reference > 0.0)) return {0.0, 0.0};
  return {std::sqrt(difference / reference), max_difference / max_reference};
}

}  // namespace

std::vector<SweepResult> sweep_contact(SceneRuntime& runtime,
                                       const std::vector<RecordedState>& states,
                                       const std::vector<SweepSetting>& settings,
                                       std::size_t max_states,
                                       const reduced::ProgressCallback& progress) {
  if (settings.empty()) throw reduced::Error("sweep_contact: no settings");
  // Whatever ends the sweep, the scene's own options are back afterwards.
  struct RestoreOptions {
    SceneRuntime& runtime;
    ~RestoreOptions() { runtime.world().set_contact_options(runtime.description().contact); }
  } restore{runtime};
  for (int h = 0; h < runtime.hand_count(); ++h) runtime.world().release(h);
  // The states in contact under the reference, evenly thinned to max_states.
  std::vector<const RecordedState*> all;
  for (const RecordedState& state : states) all.push_back(&state);
  reduced::StageProgress finding(progress, "finding the states in contact",
                                 static_cast<std::int64_t>(all.size()));
  const Replay probe = replay(runtime, all, settings.front().options, finding);
  const std::size_t wrenches =
      static_cast<std::size_t>(runtime.hand_count()) + free_objects(runtime).size();
  std::vector<const RecordedState*> touching;
  for (std::size_t i = 0; i < all.size(); ++i) {
    for (std::size_t w = 0; w < wrenches; ++w) {
      const Eigen::Vector3d& force = probe.force[i * wrenches + w];
      if (force.allFinite() && force.squaredNorm() > 0.0) {
        touching.push_back(all[i]);
        break;
      }
    }
  }
  if (touching.size() > max_states) {
    std::vector<const RecordedState*> thinned;
    for (std::size_t k = 0; k < max_states; ++k) {
      thinned.push_back(touching[k * touching.size() / max_states]);
    }
    touching = std::move(thinned);
  }

  std::vector<SweepResult> results;
  Replay reference;
  for (const SweepSetting& setting : settings) {
    reduced::StageProgress stage(progress, setting.name,
                                 static_cast<std::int64_t>(touching.size()));
    Replay r = replay(runtime, touching, setting.options, stage);
    if (results.empty()) reference = r;
    SweepResult result;
    result.name = setting.name;
    result.query_us = spread(r.us);
    for (const double n : r.nodes) result.mean_nodes += n / static_cast<double>(r.nodes.size());
    std::tie(result.force_error, result.max_force_error) =
        relative_errors(r.force, reference.force);
    result.torque_error = relative_errors(r.torque, reference.torque).first;
    result.states = touching.size();
    results.push_back(result);
  }
  return results;
}

}  // namespace khz::scene
