#pragma once
// What the scene tests share: read options for the committed test scenes and the smallest
// valid scene.

#include <khz/scene/read_scene.hpp>
#include <khz/test/fixtures.hpp>

#include <nlohmann/json.hpp>

namespace khz::scene::test_scenes {

/// Read options resolving relative mesh paths against tests/data/scenes.
inline SceneReadOptions read_options() {
  SceneReadOptions options;
  options.base_directory = test::test_file("scenes");
  return options;
}

/// A pointshell "tool" held against a distance-field "wall", both the committed cube.
inline nlohmann::json minimal_scene() {
  return nlohmann::json::parse(R"({
    "objects": [
      {"name": "tool", "mesh": "cube.off", "roles": ["pointshell"]},
      {"name": "wall", "mesh": "cube.off", "roles": ["distance_field"]}
    ],
    "haptic": {"object": "tool"}
  })");
}

}  // namespace khz::scene::test_scenes
