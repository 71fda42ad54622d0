// `khz prep SCENE --cache DIR` end to end: the summary table says what was computed and what
// was read, a second run computes nothing, and a failure exits non-zero naming the object.
// KHZ_TOOL_PATH (the khz executable) comes from tests/CMakeLists.txt.
#include <khz/test/fixtures.hpp>

#include <gtest/gtest.h>

#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <sstream>
#include <string>

namespace khz::test {
namespace {

struct KhzRun {
  int exit_code = -1;
  std::string output;  ///< stdout and stderr together
};

KhzRun khz(const std::string& arguments) {
  const std::filesystem::path output = scratch_file("khz-output.txt");
  const std::string command =
      std::string("\"") + KHZ_TOOL_PATH + "\" " + arguments + " > \"" + output.string() + "\" 2>&1";
  const int status = std::system(command.c_str());
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, read_bytes(output)};
}

/// An empty directory in the running test's scratch space (scratch_file() clears files, not
/// directories).
std::filesystem::path fresh_directory(const std::string& name) {
  const std::filesystem::path directory = scratch_file(name + ".probe").parent_path() / name;
  std::filesystem::remove_all(directory);
  return directory;
}

/// Whether some line of `text` contains every one of `words`.
bool has_line_with(const std::string& text, std::initializer_list<std::string> words) {
  std::istringstream lines(text);
  for (std::string line; std::getline(lines, line);) {
    bool all = true;
    for (const std::string& word : words) all = all && line.find(word) != std::string::npos;
    if (all) return true;
  }
  return false;
}

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
  const std::filesystem::path cache = fresh_directory("cache");
  const std::string arguments =
      "prep \"" + scene.string() + "\" --cache \"" + cache.string() + "\"";

  const KhzRun first = khz(arguments);
  ASSERT_EQ(first.exit_code, 0) << first.output;
  EXPECT_TRUE(has_line_with(first.output, {"cache: ", cache.string()})) << first.output;
  EXPECT_TRUE(has_line_with(first.output, {"wall", "distance_field", "computed", ".khzsdf"}))
      << first.output;
  EXPECT_TRUE(has_line_with(first.output, {"tool", "pointshell", "computed", ".khzshell"}))
      << first.output;
  EXPECT_TRUE(has_line_with(first.output, {"tool", "point_tree", "built"})) << first.output;
  EXPECT_TRUE(has_line_with(first.output, {"total: ", "(2 computed, 0 read, 1 built)"}))
      << first.output;

  const KhzRun second = khz(arguments);
  ASSERT_EQ(second.exit_code, 0) << second.output;
  EXPECT_TRUE(has_line_with(second.output, {"wall", "distance_field", "read"})) << second.output;
  EXPECT_TRUE(has_line_with(second.output, {"total: ", "(0 computed, 2 read, 1 built)"}))
      << second.output;
}

TEST(KhzPrep, AFailureExitsNonZeroNamingTheObject) {
  const std::filesystem::path mesh = scratch_file("broken.off");
  std::ofstream(mesh) << "OFF\n3 1 0\n0 0 0\n";  // two vertices and the triangle missing
  const std::filesystem::path cache = fresh_directory("cache");
  const KhzRun run =
      khz("prep \"" + write_scene(mesh).string() + "\" --cache \"" + cache.string() + "\"");
  EXPECT_EQ(run.exit_code, 1) << run.output;
  EXPECT_TRUE(has_line_with(run.output, {"khz: object \"wall\": distance_field: ", "broken.off"}))
      << run.output;
}

}  // namespace
}  // namespace khz::test
