// The bundled example scenes (examples/scenes/): every one reads and validates, and every one a
// program can drive (all but the hardware one) runs end to end at small settings — coarse
// fields and pointshells, small bases — with its outputs checked: forces finite and bounded,
// contact made, no failed cycle, a second preparation computing nothing, the speed-against-
// error sweep ordered as it should be, and a frame in contact showing its contact points.
#include <khz/run/frame_renderer.hpp>
#include <khz/run/held_still_device.hpp>
#include <khz/scene/contact_sweep.hpp>
#include <khz/scene/content_key.hpp>
#include <khz/scene/prepare_scene.hpp>
#include <khz/scene/read_scene.hpp>
#include <khz/scene/run_scene.hpp>
#include <khz/scene/run_summary.hpp>
#include <khz/test/fixtures.hpp>
#include <khz/test/sanitizers.hpp>

#include <nlohmann/json.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <optional>
#include <vector>

namespace khz::scene {
namespace {

std::vector<std::filesystem::path> json_files(const std::filesystem::path& directory) {
  std::vector<std::filesystem::path> files;
  for (const auto& entry : std::filesystem::directory_iterator(directory)) {
    if (entry.path().extension() == ".json") files.push_back(entry.path());
  }
  std::sort(files.begin(), files.end());
  return files;
}

std::vector<std::filesystem::path> example_scenes() { return json_files(KHZ_SCENE_EXAMPLES_DIR); }

TEST(SceneExamples, EveryExampleValidates) {
  const std::vector<std::filesystem::path> scenes = example_scenes();
  ASSERT_GE(scenes.size(), 6u) << "examples missing from " << KHZ_SCENE_EXAMPLES_DIR;
  for (const std::filesystem::path& file : scenes) {
    SCOPED_TRACE(file.string());
    SceneDescription scene;
    ASSERT_NO_THROW(scene = read_scene(file));
    EXPECT_FALSE(scene.description.empty()) << "an example says what it shows";
    for (const ObjectDescription& object : scene.objects) {
      if (object.shape.empty()) {
        EXPECT_TRUE(std::filesystem::is_regular_file(object.mesh_path)) << object.mesh_path;
      }
    }
  }
}

TEST(SceneExamples, EveryDeviceFileValidates) {
  const std::vector<std::filesystem::path> files =
      json_files(std::filesystem::path(KHZ_SCENE_EXAMPLES_DIR) / "devices");
  ASSERT_GE(files.size(), 1u);
  for (const std::filesystem::path& file : files) {
    SCOPED_TRACE(file.string());
    EXPECT_NO_THROW(read_device_file(file, 1000.0));
  }
}

TEST(SceneExamples, TheDeformableDragonOnTheDino) {
  const SceneDescription scene =
      read_scene(std::filesystem::path(KHZ_SCENE_EXAMPLES_DIR) / "dragon_on_dino.json");
  const ObjectDescription& dragon = scene.held_object();
  EXPECT_EQ(dragon.name, "dragon");
  EXPECT_TRUE(dragon.is_reduced());
  EXPECT_EQ(scene.haptic.front().role, contact::HapticObject::pointshell);
  EXPECT_TRUE(needs_product(dragon, Product::pointshell));
  EXPECT_EQ(dragon.mesh_path.filename(), "ChineseDragon-10kv.off");
  EXPECT_EQ(scene.haptic.front().device.type, DeviceType::trajectory);
}

/// The example at small settings: fields of at most 40 cells, repulsion pointshells of 32 · 4ⁱ
/// points on 3 levels, random ones of 3000 samples, 10-voxel meshes and bases of k = 4, r = 8.
/// Poses, devices, contact and coupling stay as they are.
nlohmann::json small(nlohmann::json scene) {
  for (nlohmann::json& object : scene["objects"]) {
    if (object.contains("field")) {
      nlohmann::json& field = object["field"];
      field["cells"] = std::min(field.value("cells", 128), 40);
      if (field.contains("proxies")) field["proxies"] = 20;
    }
    if (object.contains("pointshell")) {
      nlohmann::json& pointshell = object["pointshell"];
      const std::string method = pointshell.value("method", "repulsion");
      if (method == "repulsion") {
        pointshell.erase("points");
        pointshell["first_level_points"] = 32;
        pointshell["levels"] = 3;
      } else if (method == "random") {
        pointshell = {{"method", "random"},
                      {"points", 3000},
                      {"first_level_points", 16},
                      {"growth", 4},
                      {"levels", 4}};
      }
    }
    if (object.contains("model") && object["model"].value("type", "rigid") == "reduced") {
      nlohmann::json& model = object["model"];
      model["meshing"] = {{"method", "voxels"}, {"resolution", 10}, {"fill_interior", true}};
      model["basis"]["k"] = 4;
      model["basis"]["r"] = 8;
    }
  }
  return scene;
}

class SmallExample : public testing::TestWithParam<std::string> {};

TEST_P(SmallExample, RunsWithFiniteForcesContactAndACachedSecondPreparation) {
  const std::filesystem::path file =
      std::filesystem::path(KHZ_SCENE_EXAMPLES_DIR) / (GetParam() + ".json");
  std::ifstream stream(file);
  const nlohmann::json json = small(nlohmann::json::parse(stream));
  SceneReadOptions options;
  options.base_directory = KHZ_SCENE_EXAMPLES_DIR;
  const SceneDescription description = parse_scene(json.dump(), file.string(), options);

  const std::filesystem::path cache_directory = test::scratch_directory("cache");
  ProductCache cache(cache_directory);
  const PreparedScene prepared = prepare_scene(description, cache);
  EXPECT_GT(prepared.count(PrepareRecord::Origin::computed), 0);
  for (const PrepareWarning& warning : prepared.warnings) {
    ADD_FAILURE() << "object \"" << warning.object << "\": " << warning.message;
  }
  ProductCache again(cache_directory);
  EXPECT_EQ(prepare_scene(description, again).count(PrepareRecord::Origin::computed), 0)
      << "the second preparation recomputes nothing";

  scene::SceneRuntime runtime(prepared);
  std::vector<scene::RecordedState> states;
  std::optional<run::FrameSummary> contact_frame;
  const run::FrameRenderer renderer(runtime, [] {
    run::FrameOptions frame;
    frame.width = 200;
    frame.height = 150;
    return frame;
  }());
  scene::RunOptions run_options;
  run_options.frame_every = 1;
  run_options.on_frame = [&](int, scene::SceneRuntime& r) {
    states.push_back(scene::record_state(r));
    if (!contact_frame && r.world().records()[0].contact.statistics.points_in_contact > 0) {
      run::FrameSummary summary;
      renderer.render(run::capture_frame(r), &summary);
      contact_frame = summary;
    }
    return true;
  };
  const scene::HandRows rows = scene::run_scene(runtime, run_options);
  ASSERT_EQ(rows.size(), description.haptic.size());
  for (std::size_t h = 0; h < rows.size(); ++h) {
    SCOPED_TRACE("hand " + std::to_string(h));
    const scene::RunSummary summary = scene::summarize(rows[h], 1.0 / description.loop.rate_hz);
    EXPECT_TRUE(summary.finite);
    EXPECT_EQ(summary.failed_cycles, 0);
    EXPECT_GT(summary.cycles_in_contact, summary.cycles / 10) << "the example is about contact";
    EXPECT_GT(summary.max_force, 0.0);
    EXPECT_LT(summary.max_force, 200.0);
    // Within the coupling's limit and the device's own (the safety layer's clamp).
    EXPECT_LE(summary.max_rendered_force, description.coupling.max_rendered_force + 1e-9);
    EXPECT_LE(summary.max_rendered_force,
              runtime.raw_device(static_cast<int>(h)).capabilities().max_force + 1e-9);
  }
  ASSERT_TRUE(contact_frame.has_value());
  EXPECT_GT(contact_frame->in_contact, 0);
  EXPECT_GT(contact_frame->traversed, 0);

  const std::vector<scene::SweepSetting> settings =
      scene::default_sweep(description.contact, scene::tree_levels(prepared));
  std::vector<std::string> stages;
  const std::vector<scene::SweepResult> sweep =
      scene::sweep_contact(runtime, states, settings, 300, [&](const reduced::Progress& progress) {
        if (progress.done == 0) stages.emplace_back(progress.stage);
        return true;
      });
  ASSERT_GE(sweep.size(), 3u);
  // One stage to find the states in contact, then one per setting; each names what it counts.
  ASSERT_EQ(stages.size(), settings.size() + 1);
  EXPECT_EQ(stages.front(), "finding the states in contact");
  EXPECT_EQ(stages.back(), settings.back().name);
  EXPECT_GT(sweep.front().states, 0u);
  EXPECT_LE(sweep.front().states, 300u);
  // Cancelled while replaying at level 0, it stops and leaves the scene's own options in place.
  ASSERT_EQ(settings[1].options.max_level, 0);
  ASSERT_NE(description.contact.max_level, 0);
  EXPECT_THROW(scene::sweep_contact(runtime, states, settings, 300,
                                    [&](const reduced::Progress& progress) {
                                      return progress.stage != settings[1].name ||
                                             progress.done < 3;
                                    }),
               reduced::Cancelled);
  EXPECT_EQ(runtime.world().contact_options().max_level, description.contact.max_level);
  EXPECT_EQ(sweep[0].force_error, 0.0);  // the reference against itself
  EXPECT_GT(sweep[1].force_error, 0.0);  // level 0 is coarse
  EXPECT_LT(sweep[2].force_error, sweep[1].force_error) << "a finer level is closer";
  EXPECT_GT(sweep[0].mean_nodes, sweep[1].mean_nodes);
}

// Issue 19's targets at small settings: the contact and rendered force's cycle-to-cycle jumps at
// most 5 % of their peaks at the 99th percentile, no point deeper than a voxel, and a steady
// press — the scene's devices held still from the cycle of the largest contact force
// (run::HeldStillDevice) — in which, once the hands have been still for 0.3 s, the simulation
// moves by at most 1 µm and turns by at most 1e-4 rad per cycle. Under AddressSanitizer the
// queries run about ten times slower, so a scene's time budget would render coarser levels than
// any real run of it (the deformable scene's coarse level then runs away: docs/HAPTICS.md); there
// the scenes run without degradation, and the Release pass checks them with their budgets.
TEST_P(SmallExample, IsSmoothKeepsOutAndSettlesInASteadyPress) {
  const std::filesystem::path file =
      std::filesystem::path(KHZ_SCENE_EXAMPLES_DIR) / (GetParam() + ".json");
  std::ifstream stream(file);
  SceneReadOptions options;
  options.base_directory = KHZ_SCENE_EXAMPLES_DIR;
  SceneDescription description =
      parse_scene(small(nlohmann::json::parse(stream)).dump(), file.string(), options);
  if constexpr (test::sanitized_build) {
    description.contact.degradation.mode = contact::DegradationOptions::Mode::none;
  }
  ProductCache cache(test::scratch_directory("cache"));
  const PreparedScene prepared = prepare_scene(description, cache);

  SceneRuntime runtime(prepared);
  const scene::HandRows rows = scene::run_scene(runtime);
  for (int h = 0; h < runtime.hand_count(); ++h) {
    SCOPED_TRACE("hand " + std::to_string(h));
    const haptic::CycleMetricsSummary m = runtime.world().metrics(h);
    EXPECT_LE(m.contact_force_jump.p99, 0.05 * m.peak_contact_force);
    EXPECT_LE(m.rendered_force_jump.p99, 0.05 * m.peak_rendered_force);
    EXPECT_LE(m.deepest_penetration_voxels, 1.0);
    EXPECT_GT(m.peak_contact_force, 0.0);
  }

  const run::SteadyPress press = run::steady_press(prepared, rows.front(), 1.2);
  const scene::HandRows& pressed = press.rows;
  // The largest step, turn and change of step per cycle over [from, from + 0.2 s] after the hold.
  struct Motion {
    double step = 0.0, turn = 0.0, jerk = 0.0;
    int cycles = 0;
  };
  const auto motion = [&](const std::vector<scene::CycleRow>& hand_rows, double from) {
    Motion m;
    for (std::size_t i = 2; i < hand_rows.size(); ++i) {
      const double t = hand_rows[i - 2].time - press.hold_time;
      if (t < from || t > from + 0.2) continue;
      const Eigen::Vector3d step = hand_rows[i].simulation - hand_rows[i - 1].simulation;
      m.step = std::max(m.step, step.norm());
      m.jerk = std::max(
          m.jerk, (step - (hand_rows[i - 1].simulation - hand_rows[i - 2].simulation)).norm());
      m.turn =
          std::max(m.turn, hand_rows[i].orientation.angularDistance(hand_rows[i - 1].orientation));
      ++m.cycles;
    }
    return m;
  };
  // A deformed distance field rings after the press at its own frequency (the small dino's
  // lowest mode: about 14 Hz at 5 % of critical damping), and the held object rides it: elastic
  // motion, not jitter. There the press is judged once the ringing has decayed (after 1 s), and
  // the motion at 0.3 s must be smooth: its step changes by under a fifth of itself per cycle
  // (a 14 Hz swing changes it by ω T ≈ 9 %; chatter reverses it).
  const bool rings =
      std::any_of(prepared.objects.begin(), prepared.objects.end(),
                  [](const PreparedObject& o) { return o.deformed_field != nullptr; });
  // A free object the held one was pushing when the hold began slides on, and the held one
  // follows it until friction stops it: motion, not jitter, judged after 1 s too.
  const bool pushes_on = description.has_free_objects();
  for (std::size_t h = 0; h < pressed.size(); ++h) {
    SCOPED_TRACE("steady press, hand " + std::to_string(h));
    const Motion early = motion(pressed[h], 0.3), late = motion(pressed[h], 1.0);
    const Motion& judged = rings || pushes_on ? late : early;
    EXPECT_GE(judged.cycles, 150);
    EXPECT_LE(judged.step, 1e-6);
    EXPECT_LE(judged.turn, 1e-4);
    if (rings) {
      EXPECT_LE(early.jerk, 0.2 * early.step);
    }
    std::printf(
        "%s, hand %zu, still from %.3f s: after 0.3 s step %.3g m, turn %.3g rad; after 1 s "
        "step %.3g m, turn %.3g rad\n",
        GetParam().c_str(), h, press.hold_time, early.step, early.turn, late.step, late.turn);
  }
}

INSTANTIATE_TEST_SUITE_P(Examples, SmallExample,
                         testing::Values("dragon_on_dino", "dragon_on_deformable_dino",
                                         "million_point_bunny", "bunny_on_dino", "alpha_puzzle",
                                         "peg_in_hole", "two_hand_peg_in_hole", "block_push",
                                         "pick_and_place"),
                         [](const testing::TestParamInfo<std::string>& example) {
                           return example.param;
                         });

// The one example no program here can drive: it names a hardware backend.
TEST(SceneExamples, TheHardwareExampleNamesItsBackend) {
  const SceneDescription scene =
      read_scene(std::filesystem::path(KHZ_SCENE_EXAMPLES_DIR) / "bunny_on_deformable_dino.json");
  EXPECT_EQ(scene.haptic.front().device.type, DeviceType::hardware);
  EXPECT_EQ(scene.haptic.front().device.hardware_name, "dhd");
}

}  // namespace
}  // namespace khz::scene
