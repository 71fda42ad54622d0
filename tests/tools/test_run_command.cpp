// `khz run` and `khz report` end to end on a small scene: the files they promise exist and hold
// what they should (the CSV one row per cycle, PNGs that decode, a ParaView collection listing
// every frame, a report with its tables and plots), and bad requests fail with a message.
#include "khz_command.hpp"

#include <khz/render/png_file.hpp>
#include <khz/scene/cycle_log.hpp>

#include <gtest/gtest.h>

#include <fstream>
#include <string>

namespace khz::test {
namespace {

/// A 4 cm cube tool pressed 3 mm into a 10 cm cube wall and lifted, over 0.3 s; or, `sliding`,
/// pressed and slid 2 cm along the wall, with friction μ_s 0.5, μ_k 0.4.
std::filesystem::path write_scene(bool sliding = false) {
  const std::filesystem::path trajectory = scratch_file(sliding ? "slide.csv" : "press.csv");
  std::ofstream csv(trajectory);
  csv << "t,x,y,z,qw,qx,qy,qz\n0,0,0.072,0,1,0,0,0\n"
      << (sliding ? "0.1,0,0.066,0,1,0,0,0\n0.3,0.02,0.066,0,1,0,0,0\n"
                  : "0.15,0,0.066,0,1,0,0,0\n0.3,0,0.072,0,1,0,0,0\n");
  csv.close();
  const std::filesystem::path scene = scratch_file(sliding ? "sliding.json" : "scene.json");
  std::ofstream(scene) << R"({"objects": [
    {"name": "wall", "mesh": ")"
                       << test_file("scenes/cube.off").string() << R"(", "size": 0.1,
     "centre": true, "roles": ["distance_field"], "field": {"cells": 24}},
    {"name": "tool", "mesh": ")"
                       << test_file("scenes/cube.off").string() << R"(", "size": 0.04,
     "centre": true, "pose": {"position": [0, 0.072, 0]}, "roles": ["pointshell"],
     "pointshell": {"method": "random", "points": 4000, "first_level_points": 50, "growth": 4,
                    "levels": 3}}],
   "haptic": {"object": "tool"},
   "contact": {"stiffness": 2000)"
                       << (sliding ? R"(, "friction": {"static": 0.5, "kinetic": 0.4})" : "")
                       << R"(},
   "coupling": {"stiffness": 300, "saturation_force": 5},
   "device": {"type": "trajectory", "file": ")"
                       << trajectory.string() << R"(", "playback": "at_nominal_rate"},
   "loop": {"rate_hz": 1000}})";
  return scene;
}

TEST(KhzRun, WritesTheCycleLogFramesAndParaViewSeries) {
  const std::filesystem::path scene = write_scene();
  const std::filesystem::path out = scratch_directory("run");
  const std::filesystem::path cache = scratch_directory("cache");
  const KhzRun run =
      khz("run \"" + scene.string() + "\" --out \"" + out.string() + "\" --cache \"" +
          cache.string() + "\" --frames 20 --width 160 --height 120 --paraview");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_TRUE(has_line_with(run, {"cycles:", "300", "in contact"}));
  EXPECT_TRUE(has_line_with(run, {"failed cycles: 0"}));

  const std::vector<scene::CycleRow> rows = scene::read_cycle_csv(out / "cycles.csv");
  ASSERT_EQ(rows.size(), 300u);  // 0.3 s at 1 kHz (the trajectory's length)
  EXPECT_DOUBLE_EQ(rows[150].time, 0.15);
  EXPECT_GT(rows[150].contacts, 0);
  EXPECT_GT(rows[150].force.y(), 0.0);
  EXPECT_EQ(rows.front().contacts, 0);

  // The runtime's metrics in the summary: the largest contact-force jump printed is the one in
  // the log (to the 3 significant digits printed), and the passivity observer ends at the log's
  // last value.
  double largest_jump = 0.0;
  for (std::size_t k = 1; k < rows.size(); ++k) {
    largest_jump = std::max(largest_jump, (rows[k].force - rows[k - 1].force).norm());
  }
  EXPECT_GT(largest_jump, 0.0);
  const auto number_after = [&](const std::string& line_start, const std::string& word) {
    const std::size_t line = run.output.find(line_start);
    EXPECT_NE(line, std::string::npos) << run.output;
    const std::size_t at = run.output.find(word, line);
    return std::stod(run.output.substr(at + word.size()));
  };
  EXPECT_NEAR(number_after("  contact force", "max"), largest_jump, 5e-3 * largest_jump);
  EXPECT_NEAR(number_after("passivity observer:", ":"), rows.back().energy,
              1e-3 * std::abs(rows.back().energy) + 1e-12);
  EXPECT_TRUE(has_line_with(run, {"rendered force", "p99", "% of the"}));
  EXPECT_TRUE(has_line_with(run, {"equilibrium residual", "unsaturated cycles in contact"}));
  EXPECT_TRUE(has_line_with(run, {"penetration: deepest", "voxels"}));

  // 20 frames per second over 0.3 s: cycles 0, 50, …, 250.
  for (int frame = 0; frame < 6; ++frame) {
    char name[32];
    std::snprintf(name, sizeof name, "frame_%05d.png", frame);
    const render::Image image = render::read_png(out / "frames" / name);
    EXPECT_EQ(image.width(), 160);
    EXPECT_EQ(image.height(), 120);
  }
  EXPECT_FALSE(std::filesystem::exists(out / "frames" / "frame_00006.png"));

  // Per frame: the two surfaces, the tool's points and the force.
  const std::string pvd = read_bytes(out / "paraview" / "run.pvd");
  for (const char* part :
       {"part=\"wall\"", "part=\"tool\"", "part=\"points_tool\"", "part=\"force\""}) {
    std::size_t count = 0;
    for (std::size_t at = pvd.find(part); at != std::string::npos; at = pvd.find(part, at + 1)) {
      ++count;
    }
    EXPECT_EQ(count, 6u) << part;
  }
  EXPECT_TRUE(std::filesystem::exists(out / "paraview" / "run" / "points_tool_000005.vtp"));

  // A second run reads every product from the cache.
  const KhzRun again = khz("run \"" + scene.string() + "\" --out \"" + out.string() +
                           "\" --cache \"" + cache.string() + "\" --frames 0");
  ASSERT_EQ(again.exit_code, 0) << again.output;
  EXPECT_TRUE(has_line_with(again, {"total:", "(0 computed"}));
}

// Friction in `khz run`: the log counts the points that slid and the summary says how many did;
// the hand sliding the tool along the wall feels the drag. Without friction, no such line.
TEST(KhzRun, LogsAndSummarizesSlidingPoints) {
  const std::filesystem::path out = scratch_directory("sliding_run");
  const std::filesystem::path cache = scratch_directory("cache");
  const KhzRun run = khz("run \"" + write_scene(true).string() + "\" --out \"" + out.string() +
                         "\" --cache \"" + cache.string() + "\"");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_TRUE(has_line_with(run, {"friction:", "% of the points in contact slid"}));
  const std::vector<scene::CycleRow> rows = scene::read_cycle_csv(out / "cycles.csv");
  ASSERT_EQ(rows.size(), 300u);
  std::int64_t sliding = 0;
  double drag = 0.0;
  for (std::size_t k = 150; k < 280; ++k) {
    sliding += rows[k].sliding;
    drag += rows[k].rendered_force.x();
    EXPECT_LE(rows[k].sliding, rows[k].contacts);
  }
  EXPECT_GT(sliding, 0);
  EXPECT_LT(drag, 0.0) << "the drag acts against the slide (+x)";

  const KhzRun press =
      khz("run \"" + write_scene().string() + "\" --out \"" +
          scratch_directory("press_run").string() + "\" --cache \"" + cache.string() + "\"");
  ASSERT_EQ(press.exit_code, 0) << press.output;
  EXPECT_FALSE(has_line_with(press, {"friction:"}));
}

TEST(KhzReport, WritesTablesAndPlots) {
  const std::filesystem::path scene = write_scene();
  const std::filesystem::path out = scratch_directory("report");
  const KhzRun run =
      khz("report \"" + scene.string() + "\" --out \"" + out.string() + "\" --cache \"" +
          scratch_directory("cache").string() + "\" --frames 10 --width 160 --height 120");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_TRUE(has_line_with(run, {"among the 300 recorded"}));
  const std::string report = read_bytes(out / "report.md");
  // khz says how many states it replayed, and the report says the same.
  const std::string replayed = "replayed ";
  const std::size_t at = run.output.find(replayed);
  ASSERT_NE(at, std::string::npos) << run.output;
  const int states = std::stoi(run.output.substr(at + replayed.size()));
  EXPECT_GT(states, 0);
  EXPECT_LE(states, 300);
  EXPECT_NE(report.find("in contact (" + std::to_string(states) + ","), std::string::npos)
      << report;
  for (const char* text :
       {"| cycles | 300 at 1000 Hz", "| all levels (reference) |", "| level 0 |", "| level 1 |",
        "| budget 50 us |", "![speed against error](speed_vs_error.png)", "frames/frame_00000.png",
        "## Smoothness, steadiness and passivity", "| contact force jump |",
        "| equilibrium residual |", "Passivity observer", "![force jumps](jumps.png)",
        "![passivity observer](energy.png)", "## Stability map", "| as given | yes |",
        "| loop.rate_hz = 4000 |", "![stability map](stability.png)"}) {
    EXPECT_NE(report.find(text), std::string::npos) << text << "\n" << report;
  }
  for (const char* plot : {"force.png", "torque.png", "cost.png", "jumps.png", "energy.png",
                           "speed_vs_error.png", "stability.png"}) {
    const render::Image image = render::read_png(out / plot);
    EXPECT_GT(image.width(), 100) << plot;
  }
  EXPECT_TRUE(has_line_with(run, {"stability map: the scene run 12 times"}));
  // Progress names each replay's setting once: "replaying: level 0: 0.01 s".
  EXPECT_TRUE(has_line_with(run, {"replaying: level 0: "}));
  EXPECT_EQ(run.output.find("level 0: level 0"), std::string::npos) << run.output;
  EXPECT_TRUE(has_line_with(run, {"loop.rate_hz = 500:", "stable"}));

  // --no-stability leaves the map out.
  const std::filesystem::path quick = scratch_directory("report_quick");
  const KhzRun without =
      khz("report \"" + scene.string() + "\" --out \"" + quick.string() + "\" --cache \"" +
          scratch_directory("cache").string() + "\" --frames 0 --no-stability");
  ASSERT_EQ(without.exit_code, 0) << without.output;
  EXPECT_EQ(read_bytes(quick / "report.md").find("## Stability map"), std::string::npos);
  EXPECT_FALSE(std::filesystem::exists(quick / "stability.png"));
}

TEST(KhzRun, RefusesTwoDevicesAndAMissingBackend) {
  const std::filesystem::path scene = write_scene();
  const KhzRun both = khz("run \"" + scene.string() + "\" --device dhd --trajectory \"" +
                          (scene.parent_path() / "press.csv").string() + "\"");
  EXPECT_NE(both.exit_code, 0);
  EXPECT_TRUE(has_line_with(both, {"excludes"}));
  const KhzRun hardware = khz("run \"" + scene.string() + "\" --device dhd --cache \"" +
                              scratch_directory("cache").string() + "\" --out \"" +
                              scratch_directory("out").string() + "\"");
  EXPECT_EQ(hardware.exit_code, 1);
  EXPECT_TRUE(has_line_with(hardware, {"dhd", "examples/device_adapters"}));
}

}  // namespace
}  // namespace khz::test
