// Every scene under examples/scenes/ reads and validates, with its files found.
#include <khz/scene/content_key.hpp>
#include <khz/scene/read_scene.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <vector>

namespace khz::scene {
namespace {

std::vector<std::filesystem::path> example_scenes() {
  std::vector<std::filesystem::path> scenes;
  for (const auto& entry : std::filesystem::directory_iterator(KHZ_SCENE_EXAMPLES_DIR)) {
    if (entry.path().extension() == ".json") scenes.push_back(entry.path());
  }
  std::sort(scenes.begin(), scenes.end());
  return scenes;
}

TEST(SceneExamples, EveryExampleValidates) {
  const std::vector<std::filesystem::path> scenes = example_scenes();
  ASSERT_GE(scenes.size(), 2u) << "no example scenes in " << KHZ_SCENE_EXAMPLES_DIR;
  for (const std::filesystem::path& file : scenes) {
    SCOPED_TRACE(file.string());
    SceneDescription scene;
    ASSERT_NO_THROW(scene = read_scene(file));
    EXPECT_FALSE(scene.description.empty()) << "an example says what it shows";
    for (const ObjectDescription& object : scene.objects) {
      EXPECT_TRUE(std::filesystem::is_regular_file(object.mesh_path)) << object.mesh_path;
    }
  }
}

TEST(SceneExamples, TheDeformableDragonOnTheDino) {
  const SceneDescription scene =
      read_scene(std::filesystem::path(KHZ_SCENE_EXAMPLES_DIR) / "dragon_on_dino.json");
  const ObjectDescription& dragon = scene.haptic_object();
  EXPECT_EQ(dragon.name, "dragon");
  EXPECT_TRUE(dragon.is_reduced());
  EXPECT_EQ(scene.haptic.role, contact::HapticObject::pointshell);
  EXPECT_TRUE(needs_product(dragon, Product::point_tree));
  EXPECT_EQ(dragon.mesh_path.filename(), "ChineseDragon-10kv.off");
  EXPECT_EQ(scene.device.type, DeviceType::simulated_operator);
}

}  // namespace
}  // namespace khz::scene
