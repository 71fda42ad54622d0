// The stability map (khz_run, `khz report`): each point is the run the scene file with that one
// key changed gives, read and prepared independently; refused settings say why; the scene's
// description comes back unchanged, also after a cancel.
#include "scene_fixtures.hpp"

#include <khz/reduced/errors.hpp>
#include <khz/scene/prepare_scene.hpp>
#include <khz/scene/product_cache.hpp>
#include <khz/scene/run_scene.hpp>
#include <khz/scene/run_summary.hpp>
#include <khz/scene/scene_runtime.hpp>
#include <khz/scene/stability_map.hpp>

#include <gtest/gtest.h>

#include <algorithm>

namespace khz::run {
namespace {

using scene::test_scenes::cube_above_wall_scene;

/// The 4 cm cube pressed 4 mm into the wall by a simulated hand over 0.3 s and held 0.1 s.
nlohmann::json pressed_cube() {
  nlohmann::json json = cube_above_wall_scene();
  json["device"] = nlohmann::json::parse(R"({"type": "operator", "keyframes": [
      {"time": 0, "position": [0, 0.08, 0]}, {"time": 0.3, "position": [0, 0.066, 0]}]})");
  json["coupling"] = {{"stiffness", 500}, {"saturation_force", 4}};
  json["loop"] = {{"duration", 0.4}};
  return json;
}

scene::PreparedScene prepare(const nlohmann::json& json) {
  scene::ProductCache cache(test::scratch_directory("stability_cache"));
  return scene::prepare_scene(
      scene::parse_scene(json.dump(), "pressed.json", scene::test_scenes::read_options()), cache);
}

/// The metrics of one run of `prepared` as the scene gives it.
haptic::CycleMetricsSummary run_metrics(scene::PreparedScene& prepared) {
  scene::SceneRuntime runtime(prepared);
  scene::run_scene(runtime);
  return runtime.world().metrics(0);
}

TEST(StabilityMap, DefaultSettingsVaryOneParameterAtATime) {
  const scene::PreparedScene prepared = prepare(pressed_cube());
  const std::vector<scene::StabilitySetting> settings =
      scene::default_stability_settings(prepared.description);
  std::vector<std::string> names;
  for (const scene::StabilitySetting& s : settings) names.push_back(s.name());
  const std::vector<std::string> expected{"as given",
                                          "contact.stiffness = 250",
                                          "contact.stiffness = 4000",
                                          "coupling.stiffness = 125",
                                          "coupling.stiffness = 2000",
                                          "coupling.saturation_force = 1",
                                          "coupling.saturation_force = 16",
                                          "coupling.static_damping = 0.2",
                                          "coupling.static_damping = 0.9",
                                          "loop.rate_hz = 500",
                                          "loop.rate_hz = 2000",
                                          "loop.rate_hz = 4000"};
  EXPECT_EQ(names, expected);
  // No saturation to scale, and the rate the scene already has, are left out.
  nlohmann::json json = pressed_cube();
  json["coupling"].erase("saturation_force");
  json["loop"]["rate_hz"] = 2000;
  names.clear();
  for (const scene::StabilitySetting& s :
       scene::default_stability_settings(prepare(json).description)) {
    names.push_back(s.name());
  }
  EXPECT_EQ(std::count_if(names.begin(), names.end(),
                          [](const std::string& n) { return n.find("saturation") != n.npos; }),
            0);
  EXPECT_EQ(std::count(names.begin(), names.end(), "loop.rate_hz = 2000"), 0);
  EXPECT_EQ(std::count(names.begin(), names.end(), "loop.rate_hz = 1000"), 1);
}

TEST(StabilityMap, EachPointIsTheRunOfTheSceneWithThatKeyChanged) {
  scene::PreparedScene prepared = prepare(pressed_cube());
  const std::vector<scene::StabilitySetting> settings{
      {.as_given = true},
      {false, scene::StabilityParameter::coupling_stiffness, 2000.0},
      {false, scene::StabilityParameter::rate, 2000.0},
      {false, scene::StabilityParameter::static_damping, 1.5}};
  std::vector<std::string> stages;
  const std::vector<scene::StabilityPoint> points =
      scene::stability_map(prepared, settings, 0.0, {}, [&](const reduced::Progress& progress) {
        if (progress.done == 0) stages.emplace_back(progress.stage);
        return true;
      });
  ASSERT_EQ(points.size(), 4u);
  EXPECT_EQ(stages, (std::vector<std::string>{"as given", "coupling.stiffness = 2000",
                                              "loop.rate_hz = 2000"}));
  // The scene's own description is back.
  EXPECT_EQ(prepared.description.coupling.stiffness, 500.0);
  EXPECT_EQ(prepared.description.loop.rate_hz, 1000.0);
  EXPECT_EQ(prepared.description.coupling.period, 1e-3);

  // Against the scene file with the key changed, read and prepared anew: the same figures, to
  // the bit (simulated time without a time budget is reproducible).
  const auto expect_point_is = [](const scene::StabilityPoint& point, const nlohmann::json& json,
                                  double factor) {
    SCOPED_TRACE(point.setting.name());
    scene::PreparedScene reference = prepare(json);
    const haptic::CycleMetricsSummary m = run_metrics(reference);
    EXPECT_TRUE(point.refused.empty()) << point.refused;
    EXPECT_TRUE(point.finite);
    EXPECT_EQ(point.factor, factor);
    EXPECT_EQ(point.cycles,
              static_cast<std::size_t>(std::lround(0.4 * reference.description.loop.rate_hz)));
    EXPECT_GT(point.peak_contact_force, 0.0) << "the cube is pressed";
    EXPECT_EQ(point.peak_contact_force, m.peak_contact_force);
    EXPECT_EQ(point.contact_jump_p99,
              scene::percent_of(m.contact_force_jump.p99, m.peak_contact_force));
    EXPECT_EQ(point.rendered_jump_p99,
              scene::percent_of(m.rendered_force_jump.p99, m.peak_rendered_force));
    EXPECT_EQ(point.deepest_voxels, m.deepest_penetration_voxels);
    EXPECT_EQ(point.lowest_energy, m.lowest_energy);
    EXPECT_TRUE(point.stable());
  };
  expect_point_is(points[0], pressed_cube(), 1.0);
  nlohmann::json stiffer = pressed_cube();
  stiffer["coupling"]["stiffness"] = 2000;
  expect_point_is(points[1], stiffer, 4.0);
  nlohmann::json faster = pressed_cube();
  faster["loop"]["rate_hz"] = 2000;
  expect_point_is(points[2], faster, 2.0);
  EXPECT_NE(points[0].contact_jump_p99, points[1].contact_jump_p99) << "the settings differ";

  // A static damping outside [0, 1) is refused with the library's reason, and nothing runs.
  EXPECT_NE(points[3].refused.find("static_damping"), std::string::npos) << points[3].refused;
  EXPECT_EQ(points[3].cycles, 0u);
  EXPECT_FALSE(points[3].stable());
}

TEST(StabilityMap, ARateScalesTheLevelOfDetailBudgetWithThePeriod) {
  // A node-count budget (deterministic, unlike a time budget) tight enough to cut the pressed
  // cube's queries: at 2 kHz the map's run is the scene file with half the period's nodes.
  nlohmann::json json = pressed_cube();
  json["contact"]["degradation"] = {{"mode", "node_count"}, {"warm_threshold", 80}};
  scene::PreparedScene prepared = prepare(json);
  const std::vector<scene::StabilityPoint> points = scene::stability_map(
      prepared, {{.as_given = true}, {false, scene::StabilityParameter::rate, 2000.0}}, 0.0);
  ASSERT_EQ(points.size(), 2u);
  EXPECT_EQ(prepared.description.contact.degradation.warm_threshold, 80.0) << "restored";

  nlohmann::json faster = json;
  faster["loop"]["rate_hz"] = 2000;
  faster["contact"]["degradation"]["warm_threshold"] = 40;
  scene::PreparedScene reference = prepare(faster);
  const haptic::CycleMetricsSummary m = run_metrics(reference);
  EXPECT_EQ(points[1].peak_contact_force, m.peak_contact_force);
  EXPECT_EQ(points[1].contact_jump_p99,
            scene::percent_of(m.contact_force_jump.p99, m.peak_contact_force));
  EXPECT_EQ(points[1].deepest_voxels, m.deepest_penetration_voxels);
  // Not what the unscaled budget gives: the threshold matters here.
  nlohmann::json unscaled = faster;
  unscaled["contact"]["degradation"]["warm_threshold"] = 80;
  scene::PreparedScene other = prepare(unscaled);
  EXPECT_NE(run_metrics(other).peak_contact_force, m.peak_contact_force);
}

TEST(StabilityMap, StableAndSmoothFollowTheirThresholds) {
  scene::StabilityPoint p;
  EXPECT_TRUE(p.stable() && p.smooth());
  p.contact_jump_p99 = scene::smooth_jump_percent * 1.01;
  EXPECT_TRUE(p.stable());
  EXPECT_FALSE(p.smooth());
  p.contact_jump_p99 = 0.0;
  p.rendered_jump_p99 = scene::smooth_jump_percent * 1.01;
  EXPECT_FALSE(p.smooth());
  p.rendered_jump_p99 = 0.0;
  p.lowest_energy = -scene::passive_tolerance * 1.01;
  EXPECT_FALSE(p.stable() || p.smooth());
  p.lowest_energy = 0.0;
  p.finite = false;
  EXPECT_FALSE(p.stable());
}

TEST(StabilityMap, ACancelStopsAndRestoresTheScene) {
  scene::PreparedScene prepared = prepare(pressed_cube());
  const std::vector<scene::StabilitySetting> settings{
      {false, scene::StabilityParameter::rate, 4000.0}};
  EXPECT_THROW(
      scene::stability_map(prepared, settings, 0.0, {},
                           [](const reduced::Progress& progress) { return progress.done < 100; }),
      reduced::Cancelled);
  EXPECT_EQ(prepared.description.loop.rate_hz, 1000.0);
  EXPECT_EQ(prepared.description.haptic.front().device.capabilities.nominal_rate, 1000.0);
}

}  // namespace
}  // namespace khz::run
