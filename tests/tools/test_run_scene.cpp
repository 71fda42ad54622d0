// Running prepared scenes (scene::SceneRuntime and khz_run): the World a scene makes against
// libhaptic's one-pair scene and against separate queries, the simulated-time runner's
// reproducibility and its forces, the cycle log's CSV, the point classification of frames against
// the query's own counts, and the frame pictures' properties.
#include "scene_fixtures.hpp"

#include <khz/contact/query/contact_query.hpp>
#include <khz/haptic/device/null_device.hpp>
#include <khz/haptic/device/trajectory_file.hpp>
#include <khz/run/device_choice.hpp>
#include <khz/run/frame_renderer.hpp>
#include <khz/run/free_bodies.hpp>
#include <khz/run/held_still_device.hpp>
#include <khz/run/point_states.hpp>
#include <khz/run/run_realtime.hpp>
#include <khz/scene/cycle_log.hpp>
#include <khz/scene/prepare_scene.hpp>
#include <khz/scene/run_scene.hpp>
#include <khz/scene/run_summary.hpp>

#include <gtest/gtest.h>

#include <fstream>
#include <span>
#include <sstream>
#include <string>
#include <vector>

namespace khz::run {
namespace {

using scene::test_scenes::read_options;

/// A 4 cm cube "tool" (random pointshell, 3 levels) held above a 10 cm cube "wall" (field
/// 24³), whose top face is at y = 0.05; the tool starts touching it, 1 mm deep. With `second
/// wall`, a second wall "wall2" 10.5 cm to the +x side (its face at x = 0.055) that the tool
/// touches when moved there. `model` is the tool's "model" (rigid by default).
nlohmann::json cube_scene(bool second_wall = false, nlohmann::json model = {{"type", "rigid"}}) {
  nlohmann::json scene = nlohmann::json::parse(R"({
    "objects": [
      {"name": "wall", "mesh": "cube.off", "size": 0.1, "centre": true,
       "roles": ["distance_field"], "field": {"cells": 24}},
      {"name": "tool", "mesh": "cube.off", "size": 0.04, "centre": true,
       "pose": {"position": [0, 0.069, 0]}, "roles": ["pointshell"],
       "pointshell": {"method": "random", "points": 4000, "first_level_points": 50,
                      "growth": 4, "levels": 3}}
    ],
    "haptic": {"object": "tool"},
    "contact": {"stiffness": 2000, "scaling_count": 10},
    "coupling": {"stiffness": 300, "saturation_force": 5},
    "device": {"type": "null", "pose": {"position": [0, 0.069, 0]}},
    "loop": {"rate_hz": 1000, "duration": 0.2}
  })");
  scene["objects"][1]["model"] = std::move(model);
  if (second_wall) {
    scene["objects"].push_back(nlohmann::json::parse(R"(
      {"name": "wall2", "mesh": "cube.off", "size": 0.1, "centre": true,
       "pose": {"position": [0.105, 0.0, 0.0]}, "roles": ["distance_field"],
       "field": {"cells": 24}})"));
  }
  return scene;
}

scene::PreparedScene prepare(const nlohmann::json& json) {
  const scene::SceneDescription description =
      scene::parse_scene(json.dump(), "test scene", read_options());
  scene::ProductCache cache(test::scratch_directory("run-cache"));
  return scene::prepare_scene(description, cache);
}

haptic::Pose grasp_at(double x, double y, double z) {
  haptic::Pose pose;
  pose.position = {x, y, z};
  return pose;
}

/// The scene's contact with its one hand's object at grasp frame `grasp` (null if refused).
const contact::ContactWrench* probe(scene::SceneRuntime& runtime, const haptic::Pose& grasp) {
  const haptic::Pose grasps[] = {grasp};
  return runtime.world().probe(grasps) ? &runtime.world().wrench(0) : nullptr;
}

// The reference: the query of the same pair made directly, the tool's body placed by its grasp
// frame, gives the same result to round-off (each compiles the query's traversal into its own
// caller, where the compiler may fuse multiply-adds differently).
TEST(SceneRuntime, OnePairEqualsTheDirectQuery) {
  const scene::PreparedScene prepared = prepare(cube_scene());
  scene::SceneRuntime runtime(prepared);
  const contact::PointTree& tree = *prepared.objects[1].tree;
  const contact::DistanceGrid& field = *prepared.objects[0].field;
  contact::ContactWorkspace reference(tree, prepared.description.contact);
  for (const double y : {0.075, 0.0695, 0.069, 0.0685, 0.068}) {
    const haptic::Pose grasp = grasp_at(0.003, y, -0.002);
    const contact::ContactWrench* ours = probe(runtime, grasp);
    contact::ContactFrames frames;
    frames.pointshell = haptic::held_body_pose(grasp, runtime.grasp_in_body());
    frames.grasp_point = grasp.position;
    ASSERT_NE(ours, nullptr);
    ASSERT_TRUE(contact::query_contact(tree, field, frames, reference));
    const contact::ContactResult* theirs = &reference.result();
    const auto close = [](const auto& a, const auto& b) {
      return (a - b).norm() <= 1e-12 * std::max(a.norm(), b.norm());
    };
    EXPECT_TRUE(close(ours->force, theirs->force)) << "y = " << y;
    EXPECT_TRUE(close(ours->torque, theirs->torque));
    EXPECT_TRUE(close(ours->force_by_translation, theirs->force_by_translation));
    EXPECT_TRUE(close(ours->torque_by_rotation, theirs->torque_by_rotation));
    EXPECT_EQ(ours->statistics.points_in_contact, theirs->statistics.points_in_contact);
  }
  // Deep enough that the cube's bottom is in contact: the force pushes the tool up.
  EXPECT_GT(probe(runtime, grasp_at(0, 0.068, 0))->force.y(), 0.0);
}

// Two walls: the sum of two separate queries, one per wall at its own pose.
TEST(SceneRuntime, TwoPairsAddUp) {
  const scene::PreparedScene prepared = prepare(cube_scene(true));
  scene::SceneRuntime runtime(prepared);
  ASSERT_EQ(runtime.world().pairs().size(), 2u);
  const contact::PointTree& tree = *prepared.objects[1].tree;
  // In the corner: 2 mm into the first wall's top and 1 mm into the second wall's side.
  const haptic::Pose grasp = grasp_at(0.036, 0.068, 0.0);
  const contact::ContactWrench* sum = probe(runtime, grasp);
  ASSERT_NE(sum, nullptr);

  Eigen::Vector3d force = Eigen::Vector3d::Zero(), torque = Eigen::Vector3d::Zero();
  std::int64_t contacts = 0;
  for (const int wall : {0, 2}) {
    contact::ContactWorkspace workspace(tree, prepared.description.contact);
    contact::ContactFrames frames;
    frames.pointshell.translation() = grasp.position - runtime.grasp_in_body();
    frames.field.translation() =
        prepared.description.objects[static_cast<std::size_t>(wall)].pose.position;
    frames.grasp_point = grasp.position;
    ASSERT_TRUE(contact::query_contact(
        tree, *prepared.objects[static_cast<std::size_t>(wall)].field, frames, workspace));
    EXPECT_GT(workspace.result().statistics.points_in_contact, 0) << "wall " << wall;
    force += workspace.result().force;
    torque += workspace.result().torque;
    contacts += workspace.result().statistics.points_in_contact;
  }
  EXPECT_LT((sum->force - force).norm(), 1e-12 * force.norm());
  EXPECT_LT((sum->torque - torque).norm(), 1e-12 * (torque.norm() + 1e-9));
  EXPECT_EQ(sum->statistics.points_in_contact, contacts);
  EXPECT_GT(sum->force.y(), 0.0);  // pushed up by the first wall
  EXPECT_LT(sum->force.x(), 0.0);  // and back by the second
}

// A trajectory pressing the tool 3 mm into the wall and lifting it: the run is reproducible,
// every value finite, the contact force pushes up while pressed and vanishes when lifted.
TEST(RunScene, TrajectoryPressIsReproducibleAndPushesBack) {
  std::vector<haptic::TrajectorySample> samples;
  for (int i = 0; i <= 300; ++i) {
    haptic::TrajectorySample s;
    s.time = 1e-3 * i;
    const double press = i <= 150 ? i / 150.0 : (300 - i) / 150.0;
    s.pose.position = {0.0, 0.072 - 0.006 * press, 0.0};
    samples.push_back(s);
  }
  const std::filesystem::path trajectory = test::scratch_file("press.csv");
  std::ofstream(trajectory) << haptic::format_trajectory(samples, false);
  nlohmann::json json = cube_scene();
  json["device"] = {{"type", "trajectory"}, {"file", trajectory.string()}};
  json["loop"].erase("duration");
  json["objects"][1]["pose"]["position"] = {0.0, 0.072, 0.0};
  const scene::PreparedScene prepared = prepare(json);

  const auto run_once = [&] {
    scene::SceneRuntime runtime(prepared);
    EXPECT_NEAR(runtime.natural_duration(), 0.301, 1e-12);
    return scene::run_scene(runtime);
  };
  const std::vector<scene::CycleRow> rows = run_once().at(0);
  const std::vector<scene::CycleRow> again = run_once().at(0);
  ASSERT_EQ(rows.size(), 301u);
  ASSERT_EQ(again.size(), rows.size());
  for (std::size_t i = 0; i < rows.size(); ++i) {
    EXPECT_EQ(rows[i].force, again[i].force) << "cycle " << i;
    EXPECT_EQ(rows[i].simulation, again[i].simulation) << "cycle " << i;
  }
  const scene::RunSummary summary = scene::summarize(rows, 1e-3);
  EXPECT_TRUE(summary.finite);
  EXPECT_EQ(summary.failed_cycles, 0);
  EXPECT_GT(summary.cycles_in_contact, 50);
  EXPECT_GT(rows[150].force.y(), 0.5);  // pressed: pushed back up
  EXPECT_LT(std::abs(rows[150].force.x()), 0.1 * rows[150].force.y());
  EXPECT_EQ(rows.front().contacts, 0);  // starts 2 mm above
  EXPECT_EQ(rows.back().contacts, 0);   // and ends there
  // The coupling holds the tool out of the wall: the simulation stays above the manipulandum.
  EXPECT_GT(rows[150].simulation.y(), rows[150].manipulandum.y());
}

TEST(CycleLog, CsvRoundTripIsExactAndMalformedRowsNameTheirLine) {
  std::vector<scene::CycleRow> rows(3);
  rows[1].time = 1e-3;
  rows[1].force = {0.1, -2.5e-7, 3.0 / 7.0};
  rows[1].nodes = 123456789;
  rows[1].level = 4;
  rows[1].complete = false;
  rows[1].orientation = Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitX()));
  rows[2].ok = false;
  rows[2].penetration = 1.25e-4;
  rows[2].penetration_voxels = 0.3;
  rows[2].residual_force = 0.07;
  rows[2].energy = -1.0 / 3.0;
  rows[2].sliding = 7;
  const std::filesystem::path file = test::scratch_file("cycles.csv");
  scene::write_cycle_csv(rows, file);
  const std::vector<scene::CycleRow> back = scene::read_cycle_csv(file);
  ASSERT_EQ(back.size(), rows.size());
  EXPECT_EQ(back[1].force, rows[1].force);
  EXPECT_EQ(back[1].nodes, rows[1].nodes);
  EXPECT_EQ(back[1].level, 4);
  EXPECT_FALSE(back[1].complete);
  EXPECT_EQ(back[1].orientation.coeffs(), rows[1].orientation.coeffs());
  EXPECT_FALSE(back[2].ok);
  EXPECT_EQ(back[2].penetration, 1.25e-4);
  EXPECT_EQ(back[2].penetration_voxels, 0.3);
  EXPECT_EQ(back[2].residual_force, 0.07);
  EXPECT_EQ(back[2].energy, -1.0 / 3.0);
  EXPECT_EQ(back[2].sliding, 7);

  // Logs written before the last column, or the last five, existed still read, those fields 0.
  const auto without_last = [&](int columns, const char* name) {
    const std::filesystem::path earlier = test::scratch_file(name);
    std::ifstream in(file);
    std::ofstream out(earlier);
    std::string line;
    while (std::getline(in, line)) {
      for (int column = 0; column < columns; ++column) line.erase(line.rfind(','));
      out << line << "\n";
    }
    return earlier;
  };
  const std::vector<scene::CycleRow> before_sliding =
      scene::read_cycle_csv(without_last(1, "metrics_cycles.csv"));
  ASSERT_EQ(before_sliding.size(), rows.size());
  EXPECT_EQ(before_sliding[2].energy, -1.0 / 3.0);
  EXPECT_EQ(before_sliding[2].sliding, 0);
  const std::vector<scene::CycleRow> old =
      scene::read_cycle_csv(without_last(5, "legacy_cycles.csv"));
  ASSERT_EQ(old.size(), rows.size());
  EXPECT_EQ(old[1].force, rows[1].force);
  EXPECT_FALSE(old[2].ok);
  EXPECT_EQ(old[2].energy, 0.0);
  EXPECT_THROW(scene::read_cycle_csv(without_last(4, "truncated_cycles.csv")), reduced::ParseError);

  std::ofstream(file, std::ios::app) << "0.5,1,2\n";
  try {
    scene::read_cycle_csv(file);
    FAIL() << "a short row was accepted";
  } catch (const reduced::ParseError& error) {
    EXPECT_EQ(error.line(), 5);
  }
  std::ofstream(file) << "t,x,y,z\n";
  EXPECT_THROW(scene::read_cycle_csv(file), reduced::ParseError);

  // A count no integer holds (found by fuzz_cycles: converting it was undefined behaviour) or
  // a fractional level is refused, naming the column.
  std::string row = "0";
  for (int column = 1; column < 36; ++column) row += column == 16 ? ",1e300" : ",1";
  try {
    scene::parse_cycle_csv(scene::cycle_csv_header() + "\n" + row + "\n", "huge.csv");
    FAIL() << "a count of 1e300 was accepted";
  } catch (const reduced::ParseError& error) {
    EXPECT_EQ(error.line(), 2);
    EXPECT_NE(error.message().find("column 17"), std::string::npos) << error.what();
  }
  row.replace(row.find("1e300"), 5, "2.5");
  EXPECT_THROW(scene::parse_cycle_csv(scene::cycle_csv_header() + "\n" + row + "\n", "half.csv"),
               reduced::ParseError);
}

// The frame's classification finds exactly the points the query counted in contact, every one
// of them inside the field, and never classifies a point it did not place.
TEST(PointStates, ContactPointsMatchTheQuery) {
  const scene::PreparedScene prepared = prepare(cube_scene());
  scene::SceneRuntime runtime(prepared);
  for (const double y : {0.0695, 0.068, 0.066}) {
    const contact::ContactWrench* result = probe(runtime, grasp_at(0.002, y, 0.001));
    ASSERT_NE(result, nullptr);
    const std::span<const haptic::Body> bodies = runtime.world().bodies();
    const PointPicture picture =
        classify_points(bodies[1], bodies[0], result->statistics.deepest_level);
    EXPECT_EQ(picture.count(PointState::in_contact), result->statistics.points_in_contact)
        << "y = " << y;
    EXPECT_GT(picture.count(PointState::in_contact), 0);
    EXPECT_GT(picture.count(PointState::untouched), 0);  // the upper faces are culled
    const contact::DistanceGrid& field = *prepared.objects[0].field;
    for (std::size_t s = 0; s < picture.states.size(); ++s) {
      if (picture.states[s] != PointState::in_contact) continue;
      EXPECT_LT(field.distance(picture.positions.row(static_cast<Eigen::Index>(s)).transpose()),
                0.0);
    }
  }
}

// A reduced tool: its integrator is stepped under the contact and deforms.
TEST(RunScene, ReducedToolDeformsUnderContact) {
  const nlohmann::json model = nlohmann::json::parse(R"({
    "type": "reduced",
    "meshing": {"method": "voxels", "resolution": 6},
    "material": {"young_modulus": 1e5, "poisson_ratio": 0.3, "density": 1000},
    "anchors": [{"type": "half_space", "point": [0, 0.015, 0], "normal": [0, 1, 0]}],
    "basis": {"method": "modes", "k": 4, "r": 6},
    "integrator": {"mass_damping": 40}
  })");
  nlohmann::json json = cube_scene(false, model);
  json["device"]["pose"]["position"] = {0.0, 0.066, 0.0};
  const scene::PreparedScene prepared = prepare(json);
  scene::SceneRuntime runtime(prepared);
  // The largest displacement of the bottom face (in contact, free) and of the anchored top.
  double bottom = 0.0, top = 0.0;
  scene::RunOptions options;
  options.duration = 0.1;
  options.frame_every = 1;
  options.on_frame = [&](int, scene::SceneRuntime& r) {
    const reduced::VertexMatrix deformed = r.deformed_vertices(1);
    const reduced::VertexMatrix& rest = r.surface(1).vertices;
    for (Eigen::Index v = 0; v < rest.rows(); ++v) {
      double& side = rest(v, 1) < 0.0 ? bottom : top;
      side = std::max(side, (deformed.row(v) - rest.row(v)).norm());
    }
    return true;
  };
  const std::vector<scene::CycleRow> rows = scene::run_scene(runtime, options).at(0);
  ASSERT_EQ(rows.size(), 100u);
  const scene::RunSummary summary = scene::summarize(rows, 1e-3);
  EXPECT_TRUE(summary.finite);
  EXPECT_EQ(summary.failed_cycles, 0);
  EXPECT_GT(summary.cycles_in_contact, 50);
  EXPECT_GT(bottom, 1e-4);  // a tenth of a millimetre at least: pressed by newtons
  EXPECT_GT(bottom, 2.0 * top);
}

// Pictures: both objects drawn, contact-coloured points present when in contact and absent when
// not, the force arrow drawn in its colour.
TEST(FrameRenderer, ShowsObjectsContactPointsAndForce) {
  const scene::PreparedScene prepared = prepare(cube_scene());
  scene::SceneRuntime runtime(prepared);
  FrameOptions options;
  options.width = 320;
  options.height = 240;
  const auto count = [](const render::Image& image, render::Color color) {
    int n = 0;
    for (int y = 0; y < image.height(); ++y) {
      for (int x = 0; x < image.width(); ++x) n += image.pixel(x, y) == color ? 1 : 0;
    }
    return n;
  };
  const auto non_background = [](const render::Image& image) {
    int n = 0;
    for (int y = 0; y < image.height(); ++y) {
      for (int x = 0; x < image.width(); ++x) {
        n += image.pixel(x, y) == render::Color{255, 255, 255} ? 0 : 1;
      }
    }
    return n;
  };

  runtime.open_devices();
  // The null device holds it 1 mm deep; the arrow is drawn as long as the scene's radius.
  const haptic::CycleRecord& record = runtime.world().cycle(0.0, 1e-3, [] { return 0.0; }).front();
  ASSERT_GT(record.contact.force.norm(), 0.0);
  options.arrow_force = record.contact.force.norm();
  const FrameRenderer renderer(runtime, options);
  FrameSummary touching;
  const render::Image pressed = renderer.render(capture_frame(runtime), &touching);
  EXPECT_GT(touching.in_contact, 0);
  EXPECT_GT(count(pressed, options.contact_color), 5);
  EXPECT_GT(count(pressed, options.force_color), 20);
  EXPECT_GT(non_background(pressed), 320 * 240 / 10);

  EXPECT_EQ(touching.sliding, 0);
  EXPECT_EQ(count(pressed, options.sliding_color), 0);

  // With friction, anchored where it is pressed and then moved 2 mm sideways, the points that
  // slide are drawn apart: the ones the query counted.
  runtime.world().set_pair_friction(0, 1, {0.5, 0.4, 1e-4});
  const haptic::Pose held = runtime.world().coupling(0).simulation_pose();
  probe(runtime, held);
  haptic::Pose moved = held;
  moved.position.x() += 0.002;
  probe(runtime, moved);
  const std::int64_t slid = runtime.world().pair_result(0).statistics.points_sliding;
  ASSERT_GT(slid, 0);
  FrameSummary sliding;
  const render::Image slide = renderer.render(capture_frame(runtime), &sliding);
  EXPECT_EQ(sliding.sliding, slid);
  EXPECT_GT(count(slide, options.sliding_color), 5);

  runtime.world().coupling(0).reset(grasp_at(0.0, 0.09, 0.0));
  probe(runtime, grasp_at(0.0, 0.09, 0.0));
  FrameSummary apart;
  const render::Image lifted = renderer.render(capture_frame(runtime), &apart);
  EXPECT_EQ(apart.in_contact, 0);
  EXPECT_EQ(count(lifted, options.contact_color), 0);
}

// A free object (scene "dynamics", y up here) dropped 1 cm onto the fixed wall beside the held
// tool: it falls, lands and rests on the wall's top face (with friction), asleep, with the mass
// its density and mesh give; khz run's line about it says so.
TEST(RunScene, AFreeObjectFallsOntoTheWallAndComesToRest) {
  nlohmann::json json = cube_scene();
  json["objects"].push_back(nlohmann::json::parse(R"(
    {"name": "box", "mesh": "cube.off", "size": 0.04, "centre": true,
     "pose": {"position": [-0.025, 0.08, 0.0]}, "roles": ["pointshell"],
     "pointshell": {"method": "random", "points": 2000, "first_level_points": 50, "growth": 4,
                    "levels": 3},
     "dynamics": {"density": 500}})"));
  json["dynamics"] = {{"gravity", {0.0, -9.81, 0.0}}};
  // With friction, so that it stops where it lands (its random points are not symmetric).
  json["contact"]["pairs"] = nlohmann::json::parse(
      R"([{"objects": ["box", "wall"], "friction": {"static": 0.5, "kinetic": 0.4}}])");
  json["loop"]["duration"] = 0.8;
  const scene::PreparedScene prepared = prepare(json);
  scene::SceneRuntime runtime(prepared);
  const haptic::FreeBodyMotion* box = runtime.world().motion(2);
  ASSERT_NE(box, nullptr);
  EXPECT_NEAR(box->inertia().mass, 500.0 * 0.04 * 0.04 * 0.04, 1e-12);
  scene::run_scene(runtime);
  const std::vector<FreeBodyState> states = free_body_states(runtime);
  ASSERT_EQ(states.size(), 1u);
  EXPECT_EQ(states[0].name, "box");
  EXPECT_TRUE(states[0].asleep);
  EXPECT_EQ(states[0].hand, -1);
  // Resting on the top face (y = 0.05), its centre a half side above, pressed in under 1 mm.
  EXPECT_NEAR(states[0].centre.y(), 0.07, 1e-3);
  EXPECT_NEAR(states[0].centre.x(), -0.025, 1e-3);
  EXPECT_NEAR((states[0].centre - states[0].start).norm(), 0.01, 1e-3);
  std::ostringstream printed;
  print_free_bodies(printed, states);
  EXPECT_EQ(printed.str().rfind("free body \"box\": moved ", 0), 0u) << printed.str();
  EXPECT_NE(printed.str().find("; at rest\n"), std::string::npos) << printed.str();
}

// From its hold time on, a held-still device reports the pose and buttons it read then, at
// rest, whatever the device under it does: a hand holding still lets go of nothing.
TEST(HeldStillDevice, HoldsThePoseAndTheButtonsOfItsHoldTime) {
  auto null = std::make_unique<haptic::NullDevice>();
  haptic::NullDevice& device = *null;
  HeldStillDevice held(std::move(null), 0.002);
  held.open();
  device.set_pose(grasp_at(0.01, 0.0, 0.0));
  device.set_buttons(1u);
  haptic::DeviceState state;
  do {
    ASSERT_TRUE(held.read(state));
  } while (state.time < 0.002);
  device.set_pose(grasp_at(0.0, 0.02, 0.0));
  device.set_buttons(0u);
  ASSERT_TRUE(held.read(state));
  EXPECT_EQ(state.pose.position, Eigen::Vector3d(0.01, 0.0, 0.0));
  EXPECT_EQ(state.buttons, 1u);
  EXPECT_EQ(state.linear_velocity, Eigen::Vector3d::Zero());
}

// The real-time loop runs the same cycle: every cycle is logged at its scheduled time, a
// period or more apart, the press gives contact, and the device is closed afterwards.
TEST(RunSceneRealtime, RunsEveryCycleOnTheLoopAndClosesTheDevice) {
  const scene::PreparedScene prepared = prepare(cube_scene());
  scene::SceneRuntime runtime(prepared);
  const RealtimeRun run = run_scene_realtime(runtime, 0.2);
  ASSERT_EQ(run.rows.size(), 1u);
  const std::vector<scene::CycleRow>& rows = run.rows.front();
  ASSERT_EQ(rows.size(), 200u);
  for (std::size_t i = 1; i < rows.size(); ++i) {
    EXPECT_GE(rows[i].time - rows[i - 1].time, 1e-3 - 1e-12) << "cycle " << i;
  }
  EXPECT_GE(run.loop.cycles, 200);
  const scene::RunSummary summary = scene::summarize(rows, 1e-3);
  EXPECT_TRUE(summary.finite);
  EXPECT_EQ(summary.failed_cycles, 0);
  EXPECT_EQ(summary.cycles_in_contact, 200);  // held 1 mm deep by the null device
  EXPECT_FALSE(runtime.device().is_open());
}

TEST(RunScene, NullDeviceWithoutDurationIsRefusedWithAHint) {
  nlohmann::json json = cube_scene();
  json["loop"].erase("duration");
  const scene::PreparedScene prepared = prepare(json);
  scene::SceneRuntime runtime(prepared);
  try {
    scene::run_scene(runtime);
    FAIL() << "ran without a duration";
  } catch (const reduced::Error& error) {
    EXPECT_NE(std::string(error.what()).find("--duration"), std::string::npos) << error.what();
  }
}

TEST(ChooseDevices, HardwareIsRefusedNamingTheAdapters) {
  const scene::PreparedScene prepared = prepare(cube_scene());
  DeviceChoice choice;
  choice.hardware = "openhaptics";
  const std::vector<scene::DeviceDescription> devices =
      choose_devices(prepared.description, choice);
  try {
    scene::SceneRuntime runtime(prepared, devices);
    FAIL() << "made a hardware device";
  } catch (const reduced::Error& error) {
    EXPECT_NE(std::string(error.what()).find("examples/device_adapters"), std::string::npos);
  }
  choice.trajectory = "a.csv";
  EXPECT_THROW(choose_devices(prepared.description, choice), reduced::Error);
}

// The runtime's devices: one per hand, checked; a null entry keeps the scene's own.
TEST(SceneRuntime, TakesOneDevicePerHand) {
  const scene::PreparedScene prepared = prepare(cube_scene());
  EXPECT_THROW(scene::SceneRuntime(prepared, std::vector<scene::DeviceDescription>{}),
               reduced::Error);
  std::vector<haptic::Device*> two(2, nullptr);
  EXPECT_THROW(scene::SceneRuntime(prepared, std::span<haptic::Device* const>(two)),
               reduced::Error);
  const std::vector<haptic::Device*> scene_own(1, nullptr);
  scene::SceneRuntime runtime(prepared, std::span<haptic::Device* const>(scene_own));
  EXPECT_NE(dynamic_cast<haptic::NullDevice*>(&runtime.raw_device()), nullptr);
  EXPECT_EQ(runtime.hand_count(), 1);
  EXPECT_EQ(runtime.held_object(), 1);
}

}  // namespace
}  // namespace khz::run
