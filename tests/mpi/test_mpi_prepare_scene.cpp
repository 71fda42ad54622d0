// `mpirun -np 2`: a scene prepared by the ranks of a job writes the files one process writes,
// byte for byte, so that one process afterwards computes nothing; a failure or a cancel on one
// rank ends the preparation on both and leaves no partial file (issue 24, item 4).
#include "scene_fixtures.hpp"

#include <khz/mpi/mpi_work_group.hpp>
#include <khz/reduced/errors.hpp>
#include <khz/reduced/worker_threads.hpp>
#include <khz/scene/prepare_error.hpp>
#include <khz/scene/prepare_scene.hpp>
#include <khz/scene/read_scene.hpp>
#include <khz/test/fixtures.hpp>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <filesystem>
#include <set>
#include <string>
#include <vector>

namespace khz::scene {
namespace {

using Json = nlohmann::json;

SceneDescription scene_of(const Json& scene) {
  SceneReadOptions options;
  options.base_directory = test::test_file("scenes");
  return parse_scene(scene.dump(), "scene.json", options);
}

/// A scratch directory both ranks use: emptied by one rank after the other, then used.
std::filesystem::path shared_directory(mpi::MpiWorkGroup& group, const std::string& name) {
  std::filesystem::path directory;
  for (int turn = 0; turn < group.size(); ++turn) {
    if (turn == group.rank()) directory = test::scratch_directory(name);
    double barrier = 0.0;
    group.sum({&barrier, 1});
  }
  return directory;
}

std::vector<std::string> file_names(const std::filesystem::path& directory) {
  std::vector<std::string> names;
  if (!std::filesystem::exists(directory)) return names;
  for (const auto& entry : std::filesystem::directory_iterator(directory)) {
    names.push_back(entry.path().filename().string());
  }
  std::sort(names.begin(), names.end());
  return names;
}

bool has_partial_file(const std::filesystem::path& directory) {
  const std::vector<std::string> names = file_names(directory);
  return std::any_of(names.begin(), names.end(), [](const std::string& name) {
    return name.find(".partial-") != std::string::npos;
  });
}

TEST(MpiPrepareScene, WritesTheFilesOneProcessWritesAndTheNextRunReadsThem) {
  mpi::MpiWorkGroup group;
  // The reduced polynomials' sums are ordered by thread: equal bytes need equal thread counts.
  const reduced::ScopedWorkerThreads one_thread(1);
  const SceneDescription scene = scene_of(test_scenes::reduced_pair_scene());
  const std::filesystem::path alone = shared_directory(group, "alone");
  const std::filesystem::path shared = shared_directory(group, "shared");
  if (group.rank() == 0) {
    ProductCache cache(alone);
    prepare_scene(scene, cache);
  }

  ProductCache cache(shared);
  PrepareOptions options;
  options.group = &group;
  const PreparedScene prepared = prepare_scene(scene, cache, options);

  // Four products to start with (two models, two fields), then the tool's pointshell: each
  // computed by one rank, both ranks busy.
  std::set<int> ranks;
  int computed = 0;
  for (const PrepareRecord& record : prepared.records) {
    if (record.origin != PrepareRecord::Origin::computed) continue;
    ++computed;
    ranks.insert(record.rank);
    EXPECT_GE(record.seconds, 0.0);
  }
  EXPECT_EQ(computed, 7);  // 2 volume meshes, 2 models, 2 fields, the pointshell
  EXPECT_EQ(ranks, (std::set<int>{0, 1}));
  // EXPECT, never ASSERT, in these tests: a rank that left a test early would leave the other
  // waiting in a collective.
  EXPECT_TRUE(prepared.objects[0].model && prepared.objects[0].deformable_tree);
  EXPECT_TRUE(prepared.objects[1].deformed_field);

  double barrier = 0.0;
  group.sum({&barrier, 1});  // rank 0's reference is written
  EXPECT_EQ(file_names(shared), file_names(alone));
  for (const std::string& name : file_names(alone)) {
    EXPECT_EQ(test::read_bytes(shared / name), test::read_bytes(alone / name)) << name;
  }
  EXPECT_EQ(file_names(shared).size(), 7U);

  group.sum({&barrier, 1});  // both have compared before anyone reads again
  if (group.rank() == 0) {
    ProductCache again(shared);
    prepare_scene(scene, again);
    EXPECT_EQ(again.computed_count(), 0);
  }
}

/// A rigid wall (its field goes to rank 0) and a reduced tool whose anchors select no vertex
/// (its model goes to rank 1, where it fails; its field to rank 0).
Json scene_failing_on_rank_1() {
  Json scene = test_scenes::reduced_pair_scene();
  std::swap(scene["objects"][0], scene["objects"][1]);
  Json& wall = scene["objects"][0];
  wall.erase("model");
  wall["field"] = {{"cells", 16}};
  scene["objects"][1]["model"]["anchors"] = {
      {{"type", "box"}, {"min", {5, 5, 5}}, {"max", {6, 6, 6}}}};
  return scene;
}

TEST(MpiPrepareScene, AFailureOnOneRankEndsEveryRankAndLeavesNoPartialFile) {
  mpi::MpiWorkGroup group;
  const std::filesystem::path directory = shared_directory(group, "failure");
  ProductCache cache(directory);
  PrepareOptions options;
  options.group = &group;
  try {
    prepare_scene(scene_of(scene_failing_on_rank_1()), cache, options);
    ADD_FAILURE() << "rank " << group.rank() << ": no error";
  } catch (const PrepareError& error) {  // the rank that failed: its own error
    EXPECT_EQ(group.rank(), 1);
    EXPECT_EQ(error.object(), "tool");
    EXPECT_NE(error.cause().find("anchor"), std::string::npos) << error.what();
  } catch (const reduced::Error& error) {  // the other: what failed, where
    EXPECT_EQ(group.rank(), 0);
    const std::string message = error.what();
    EXPECT_NE(message.find("failed on rank 1 of 2"), std::string::npos) << message;
    EXPECT_NE(message.find("object \"tool\""), std::string::npos) << message;
  }
  double barrier = 0.0;
  group.sum({&barrier, 1});
  EXPECT_FALSE(has_partial_file(directory));
  // Kept: what was complete before the failure (both fields on rank 0; the tool's volume mesh,
  // fetched before its model, on rank 1). Never the model that failed.
  const std::vector<std::string> names = file_names(directory);
  EXPECT_EQ(names.size(), 3U);
  EXPECT_EQ(
      std::count_if(names.begin(), names.end(),
                    [](const std::string& name) { return name.rfind("distance_field-", 0) == 0; }),
      2);
  EXPECT_TRUE(std::none_of(names.begin(), names.end(), [](const std::string& name) {
    return name.rfind("reduced_model-", 0) == 0;
  }));
}

TEST(MpiPrepareScene, AMeshOnlyOneRankCannotReadFailsEveryRank) {
  mpi::MpiWorkGroup group;
  const std::filesystem::path directory = shared_directory(group, "unreadable");
  Json scene = test_scenes::reduced_pair_scene();
  const std::filesystem::path mesh = directory / "rank0-wall.off";  // rank 1 has none
  if (group.rank() == 0) {
    std::filesystem::create_directories(directory);
    std::filesystem::copy_file(test::test_file("scenes/cube.off"), mesh);
  }
  scene["objects"][1]["mesh"] = (directory / ("rank" + std::to_string(group.rank()) + "-wall.off"))
                                    .string();  // rank 1's is missing
  SceneReadOptions read_options;
  read_options.base_directory = test::test_file("scenes");
  read_options.check_files = false;
  const SceneDescription description = parse_scene(scene.dump(), "scene.json", read_options);
  ProductCache cache(directory / "cache");
  PrepareOptions options;
  options.group = &group;
  try {
    prepare_scene(description, cache, options);
    ADD_FAILURE() << "rank " << group.rank() << ": no error";
  } catch (const reduced::Error& error) {
    const std::string message = error.what();
    if (group.rank() == 0) {
      EXPECT_NE(message.find("preparing the scene failed on rank 1 of 2"), std::string::npos)
          << message;
    }
    EXPECT_NE(message.find("rank1-wall.off"), std::string::npos) << message;
  }
}

TEST(MpiPrepareScene, ACancelOnOneRankCancelsEveryRank) {
  mpi::MpiWorkGroup group;
  const std::filesystem::path directory = shared_directory(group, "cancel");
  ProductCache cache(directory);
  PrepareOptions options;
  options.group = &group;
  options.progress = [&](const std::string&, PrepareStep, const reduced::Progress&) {
    return group.rank() != 1;
  };
  EXPECT_THROW(prepare_scene(scene_of(test_scenes::reduced_pair_scene()), cache, options),
               reduced::Cancelled);
  double barrier = 0.0;
  group.sum({&barrier, 1});
  EXPECT_FALSE(has_partial_file(directory));
}

}  // namespace
}  // namespace khz::scene
