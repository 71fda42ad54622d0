// What the interactive viewer says while it prepares a scene (khz_viewer_input), headless: one
// line per product, "cached" for what is read from the product cache and "preparing" for what
// is computed or built, checked against scene::prepare_scene()'s own records.
#include "scene_fixtures.hpp"

#include <khz/scene/prepare_scene.hpp>
#include <khz/viewer/preparation_messages.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace khz::viewer {
namespace {

using Origin = scene::PrepareRecord::Origin;

TEST(PreparationMessages, OneLinePerProductFromItsFirstReport) {
  PreparationMessages messages;
  const auto report = [](const char* stage, std::int64_t done) {
    return reduced::Progress{stage, done, 3};
  };
  EXPECT_EQ(messages.line("plate", scene::PrepareStep::distance_field, report("reading", 0)),
            "plate distance_field: cached");
  EXPECT_EQ(messages.line("plate", scene::PrepareStep::distance_field, report("reading", 1)), "");
  EXPECT_EQ(messages.line("peg", scene::PrepareStep::pointshell, report("repulsion", 0)),
            "preparing peg pointshell ...");
  EXPECT_EQ(messages.line("peg", scene::PrepareStep::pointshell, report("repulsion", 2)), "");
  // The surface mesh is read for a computation: not a cache read.
  EXPECT_EQ(
      messages.line("peg", scene::PrepareStep::point_tree, report("reading the surface mesh", 0)),
      "preparing peg point_tree ...");
  EXPECT_EQ(messages.line("peg", scene::PrepareStep::point_tree, report("reading", 0)), "");
  // A new object with the step just announced is a new product.
  EXPECT_EQ(messages.line("peg2", scene::PrepareStep::point_tree, report("reading", 0)),
            "peg2 point_tree: cached");
}

/// Prepares `description` through the cache in `directory`, keeping the lines the viewer would
/// print.
scene::PreparedScene prepare(const scene::SceneDescription& description,
                             const std::filesystem::path& directory,
                             std::vector<std::string>& lines) {
  scene::ProductCache cache(directory);
  PreparationMessages messages;
  scene::PrepareOptions options;
  options.progress = [&](const std::string& object, scene::PrepareStep step,
                         const reduced::Progress& progress) {
    std::string line = messages.line(object, step, progress);
    if (!line.empty()) lines.push_back(std::move(line));
    return true;
  };
  return scene::prepare_scene(description, cache, options);
}

/// The line the viewer should print for each record.
std::vector<std::string> expected_lines(const scene::PreparedScene& prepared) {
  std::vector<std::string> lines;
  for (const scene::PrepareRecord& record : prepared.records) {
    const std::string product = record.object + " " + std::string(scene::step_name(record.step));
    lines.push_back(record.origin == Origin::read ? product + ": cached"
                                                  : "preparing " + product + " ...");
  }
  return lines;
}

TEST(PreparationMessages, CachedExactlyForTheProductsReadFromTheCache) {
  const scene::SceneDescription description =
      scene::parse_scene(scene::test_scenes::reduced_pair_scene().dump(), "reduced scene",
                         scene::test_scenes::read_options());
  const std::filesystem::path directory = test::scratch_directory("viewer-cache");

  std::vector<std::string> first;
  const scene::PreparedScene computed = prepare(description, directory, first);
  ASSERT_EQ(computed.count(Origin::read), 0);
  EXPECT_EQ(first, expected_lines(computed));
  EXPECT_TRUE(std::none_of(first.begin(), first.end(), [](const std::string& line) {
    return line.find("cached") != std::string::npos;
  }));
  EXPECT_EQ(preparation_summary(computed).substr(0, 12), "prepared in ");
  EXPECT_NE(preparation_summary(computed).find(": 0 cached, 7 computed, 2 built"),
            std::string::npos)
      << preparation_summary(computed);

  std::vector<std::string> second;
  const scene::PreparedScene cached = prepare(description, directory, second);
  ASSERT_EQ(cached.count(Origin::computed), 0);
  ASSERT_GT(cached.count(Origin::read), 0);
  EXPECT_EQ(second, expected_lines(cached));
  EXPECT_NE(std::find(second.begin(), second.end(), "tool reduced_model: cached"), second.end());
  EXPECT_NE(std::find(second.begin(), second.end(), "tool pointshell: cached"), second.end());
  for (const char* built : {"preparing tool point_tree ...", "preparing wall deformed_field ..."}) {
    EXPECT_NE(std::find(second.begin(), second.end(), built), second.end()) << built;
  }  // built anew every time
  EXPECT_NE(preparation_summary(cached).find(": 6 cached, 0 computed, 2 built"), std::string::npos)
      << preparation_summary(cached);
}

}  // namespace
}  // namespace khz::viewer
