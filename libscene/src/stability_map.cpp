#include <khz/scene/stability_map.hpp>

#include <khz/reduced/stage_progress.hpp>
#include <khz/scene/run_scene.hpp>
#include <khz/scene/run_summary.hpp>
#include <khz/scene/scene_runtime.hpp>

#include <cmath>
#include <sstream>

namespace khz::scene {
namespace {

/// Where `parameter` lives in a SceneDescription (const or not): the key's field, the rate's
/// derived values aside.
template <typename Scene>
auto& field_of(Scene& scene, StabilityParameter parameter) noexcept {
  switch (parameter) {
    case StabilityParameter::contact_stiffness:
      return scene.contact.stiffness;
    case StabilityParameter::coupling_stiffness:
      return scene.coupling.stiffness;
    case StabilityParameter::saturation_force:
      return scene.coupling.saturation_force;
    case StabilityParameter::static_damping:
      return scene.coupling.static_damping;
    case StabilityParameter::rate:
      break;
  }
  return scene.loop.rate_hz;
}

/// Sets one parameter in `scene` as the scene reader would have from the key.
/// A new rate also scales the level-of-detail budget with the period (a time budget, or a node
/// count standing for one), as a user changing the rate would: the same share of each cycle.
void apply(const StabilitySetting& setting, SceneDescription& scene) {
  if (setting.as_given) return;
  const double given_rate = scene.loop.rate_hz;
  field_of(scene, setting.parameter) = setting.value;
  if (setting.parameter != StabilityParameter::rate) return;
  const double period_ratio = given_rate / setting.value;
  scene.contact.degradation.budget_microseconds *= period_ratio;
  scene.contact.degradation.warm_threshold *= period_ratio;
  // What read_scene() derives from loop.rate_hz: the coupling's period and every device's rate
  // (a simulated operator checks it can integrate at it).
  scene.coupling.period = 1.0 / setting.value;
  for (HapticDescription& hand : scene.haptic) {
    hand.device.capabilities.nominal_rate = setting.value;
    hand.device.simulated_operator.capabilities.nominal_rate = setting.value;
    if (hand.device.type == DeviceType::simulated_operator) {
      hand.device.simulated_operator.validate();
    }
  }
}

/// Puts prepared.description back however the run ends.
class RestoreDescription {
 public:
  explicit RestoreDescription(PreparedScene& prepared)
      : m_prepared(prepared), m_saved(prepared.description) {}
  ~RestoreDescription() { m_prepared.description = m_saved; }
  RestoreDescription(const RestoreDescription&) = delete;
  RestoreDescription& operator=(const RestoreDescription&) = delete;

 private:
  PreparedScene& m_prepared;
  SceneDescription m_saved;
};

}  // namespace

std::string_view parameter_key(StabilityParameter parameter) noexcept {
  switch (parameter) {
    case StabilityParameter::contact_stiffness:
      return "contact.stiffness";
    case StabilityParameter::coupling_stiffness:
      return "coupling.stiffness";
    case StabilityParameter::saturation_force:
      return "coupling.saturation_force";
    case StabilityParameter::static_damping:
      return "coupling.static_damping";
    case StabilityParameter::rate:
      return "loop.rate_hz";
  }
  return "?";
}

std::string StabilitySetting::name() const {
  if (as_given) return "as given";
  std::ostringstream text;
  text << parameter_key(parameter) << " = " << value;
  return text.str();
}

bool StabilityPoint::stable() const noexcept {
  return refused.empty() && finite && lowest_energy >= -passive_tolerance;
}

bool StabilityPoint::smooth() const noexcept {
  return stable() && contact_jump_p99 <= smooth_jump_percent &&
         rendered_jump_p99 <= smooth_jump_percent;
}

std::vector<StabilitySetting> default_stability_settings(const SceneDescription& scene) {
  std::vector<StabilitySetting> settings{{.as_given = true}};
  const auto scaled = [&](StabilityParameter parameter, double given) {
    if (!std::isfinite(given)) return;  // e.g. no saturation: nothing to scale
    for (const double factor : {0.25, 4.0}) settings.push_back({false, parameter, factor * given});
  };
  const auto each = [&](StabilityParameter parameter, double given,
                        std::initializer_list<double> values) {
    for (const double value : values) {
      if (value != given) settings.push_back({false, parameter, value});
    }
  };
  for (const StabilityParameter parameter :
       {StabilityParameter::contact_stiffness, StabilityParameter::coupling_stiffness,
        StabilityParameter::saturation_force}) {
    scaled(parameter, field_of(scene, parameter));
  }
  each(StabilityParameter::static_damping, scene.coupling.static_damping, {0.2, 0.9});
  each(StabilityParameter::rate, scene.loop.rate_hz, {500.0, 1000.0, 2000.0, 4000.0});
  return settings;
}

std::vector<StabilityPoint> stability_map(PreparedScene& prepared,
                                          const std::vector<StabilitySetting>& settings,
                                          double duration,
                                          const std::vector<DeviceDescription>& devices,
                                          const reduced::ProgressCallback& progress) {
  const RestoreDescription restore(prepared);
  SceneDescription given = prepared.description;
  if (!devices.empty()) {
    if (devices.size() != given.haptic.size()) {
      throw reduced::Error("stability_map: " + std::to_string(devices.size()) +
                           " devices for a scene of " + std::to_string(given.haptic.size()) +
                           " hands");
    }
    for (std::size_t h = 0; h < devices.size(); ++h) given.haptic[h].device = devices[h];
  }
  std::vector<StabilityPoint> points;
  for (const StabilitySetting& setting : settings) {
    StabilityPoint point;
    point.setting = setting;
    if (!setting.as_given) point.factor = setting.value / field_of(given, setting.parameter);
    prepared.description = given;
    std::unique_ptr<SceneRuntime> runtime;
    try {
      apply(setting, prepared.description);
      runtime = std::make_unique<SceneRuntime>(prepared);
    } catch (const reduced::Error& error) {
      point.refused = error.what();
      points.push_back(point);
      continue;
    }
    const std::size_t cycles = run_cycles(*runtime, duration);
    const std::string stage_name = point.setting.name();  // StageProgress keeps a view of it
    reduced::StageProgress stage(progress, stage_name, static_cast<std::int64_t>(cycles));
    RunOptions options;
    options.duration = duration;
    options.frame_every = std::max(1, static_cast<int>(prepared.description.loop.rate_hz / 20.0));
    options.on_frame = [&](int cycle, SceneRuntime&) {
      if (cycle > stage.done()) stage.advance(cycle - stage.done());
      return true;
    };
    const HandRows rows = run_scene(*runtime, options);
    stage.finish();
    const RunSummary summary = summarize(rows.front(), 1.0 / prepared.description.loop.rate_hz);
    const haptic::CycleMetricsSummary m = runtime->world().metrics(0);
    point.finite = summary.finite && summary.failed_cycles == 0;
    point.cycles = rows.front().size();
    point.peak_contact_force = m.peak_contact_force;
    point.contact_jump_p99 = percent_of(m.contact_force_jump.p99, m.peak_contact_force);
    point.rendered_jump_p99 = percent_of(m.rendered_force_jump.p99, m.peak_rendered_force);
    point.still_step_p99 = m.still_translation.p99;
    point.still_cycles = m.still_translation.count;
    point.deepest_voxels = m.deepest_penetration_voxels;
    point.lowest_energy = m.lowest_energy;
    points.push_back(point);
  }
  return points;
}

}  // namespace khz::scene
