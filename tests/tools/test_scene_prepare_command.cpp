// `khz prep SCENE --cache DIR` end to end: the summary table says what was computed and what
// was read, a second run computes nothing, and a failure exits non-zero naming the object.
#include "khz_command.hpp"

#include <khz/test/fixtures.hpp>

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

namespace khz::test {
namespace {

/// A scene file in the test's scratch directory: a rigid field "wall" and a rigid random
/// pointshell "tool", both made of `mesh`.
std::filesystem::path write_scene(const std::filesystem::path& mesh) {
  const std::filesystem::path scene = scratch_file("scene.json");
  std::ofstream(scene) << R"({"objects": [
    {"name": "wall", "mesh": ")"
                       << mesh.string() << R"(", "size": 0.1, "centre": true,
     "roles": ["distance_field"], "field": {"cells": 16}},
    {"name": "tool", "mesh": ")"
                       << mesh.string() << R"(", "size": 0.05, "centre": true,
     "roles": ["pointshell"], "pointshell": {"method": "random", "points": 200}}],
  "haptic": {"object": "tool"}})";
  return scene;
}

TEST(KhzPrep, ComputesThenReadsAndSummarizes) {
  const std::filesystem::path scene = write_scene(test_file("scenes/cube.off"));
  const std::filesystem::path cache = scratch_directory("cache");
  const std::string arguments =
      "prep \"" + scene.string() + "\" --cache \"" + cache.string() + "\"";

  const KhzRun first = khz(arguments);
  ASSERT_EQ(first.exit_code, 0) << first.output;
  EXPECT_TRUE(has_line_with(first, {"cache: ", cache.string()}));
  EXPECT_TRUE(has_line_with(first, {"wall", "distance_field", "computed", ".khzsdf"}));
  EXPECT_TRUE(has_line_with(first, {"tool", "pointshell", "computed", ".khzshell"}));
  EXPECT_TRUE(has_line_with(first, {"tool", "point_tree", "built"}));
  EXPECT_TRUE(has_line_with(first, {"total: ", "(2 computed, 0 read, 1 built)"}));

  const KhzRun second = khz(arguments);
  ASSERT_EQ(second.exit_code, 0) << second.output;
  EXPECT_TRUE(has_line_with(second, {"wall", "distance_field", "read"}));
  EXPECT_TRUE(has_line_with(second, {"total: ", "(0 computed, 2 read, 1 built)"}));
}

// KHZ_THREADS bounds the tool's threads (test_reduced_worker_threads counts them); a value that
// is not a thread count stops it before it does anything, naming the variable.
TEST(KhzPrep, TakesItsThreadCountFromKhzThreads) {
  const std::filesystem::path scene = write_scene(test_file("scenes/cube.off"));
  const std::string arguments =
      "prep \"" + scene.string() + "\" --cache \"" + scratch_directory("cache").string() + "\"";
  ASSERT_EQ(setenv("KHZ_THREADS", "1", 1), 0);
  const KhzRun one = khz(arguments);
  EXPECT_EQ(one.exit_code, 0) << one.output;
  ASSERT_EQ(setenv("KHZ_THREADS", "two", 1), 0);
  const KhzRun bad = khz(arguments);
  ASSERT_EQ(unsetenv("KHZ_THREADS"), 0);
  EXPECT_EQ(bad.exit_code, 1) << bad.output;
  EXPECT_TRUE(has_line_with(bad, {"khz: the environment variable KHZ_THREADS must be a whole "
                                  "number of threads ≥ 1, got \"two\""}));
}

TEST(KhzPrep, AFailureExitsNonZeroNamingTheObject) {
  const std::filesystem::path mesh = scratch_file("broken.off");
  std::ofstream(mesh) << "OFF\n3 1 0\n0 0 0\n";  // two vertices and the triangle missing
  const std::filesystem::path cache = scratch_directory("cache");
  const KhzRun run =
      khz("prep \"" + write_scene(mesh).string() + "\" --cache \"" + cache.string() + "\"");
  EXPECT_EQ(run.exit_code, 1) << run.output;
  EXPECT_TRUE(has_line_with(run, {"khz: object \"wall\": distance_field: ", "broken.off"}));
}

}  // namespace
}  // namespace khz::test
