#pragma once
// What the scene tests share: read options for the committed test scenes, the smallest valid
// scene, and small rigid and reduced scenes in contact.

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

/// A reduced 8 cm cube with a repulsion pointshell (16 + 64 points on its 16-cell field; 4³
/// voxels, bottom layer anchored, r = 4 from k = 3 modes and their derivatives) held against a
/// reduced 10 cm cube used as a deformed distance field (4³ voxels, r = 3 linear modes, 12
/// proxies).
inline nlohmann::json reduced_pair_scene() {
  return nlohmann::json::parse(R"({
    "objects": [
      {"name": "tool", "mesh": "cube.off", "size": 0.08, "centre": true, "roles": ["pointshell"],
       "model": {
         "type": "reduced",
         "meshing": {"method": "voxels", "resolution": 4, "fill_interior": true},
         "material": {"young_modulus": 1e5, "poisson_ratio": 0.4, "density": 1000},
         "anchors": [{"type": "box", "min": [-1, -1, -1], "max": [1, 1, -0.035]}],
         "basis": {"method": "modes", "k": 3, "r": 4}
       },
       "field": {"cells": 16},
       "pointshell": {"method": "repulsion", "first_level_points": 16, "levels": 2}},
      {"name": "wall", "mesh": "cube.off", "size": 0.1, "centre": true,
       "roles": ["distance_field"],
       "model": {
         "type": "reduced",
         "meshing": {"method": "voxels", "resolution": 4, "fill_interior": true},
         "material": {"young_modulus": 1e5, "poisson_ratio": 0.4, "density": 1000},
         "anchors": [{"type": "half_space", "point": [0, 0, -0.04], "normal": [0, 0, -1]}],
         "basis": {"method": "modes", "k": 3, "modal_derivatives": false}
       },
       "field": {"cells": 16, "proxies": 12, "neighbours": 4}}
    ],
    "haptic": {"object": "tool"}
  })");
}

/// A 4 cm cube "tool" (500 random points) 1 cm above a 10 cm cube "wall" (16³ field, top face
/// at y = 0.05), both centred: minimal_scene() sized for contact.
inline nlohmann::json cube_above_wall_scene() {
  nlohmann::json json = minimal_scene();
  nlohmann::json& tool = json["objects"][0];
  tool["size"] = 0.04;
  tool["centre"] = true;
  tool["pose"] = {{"position", {0.0, 0.08, 0.0}}};
  tool["pointshell"] = {{"method", "random"}, {"points", 500}};
  nlohmann::json& wall = json["objects"][1];
  wall["size"] = 0.1;
  wall["centre"] = true;
  wall["field"] = {{"cells", 16}};
  return json;
}

}  // namespace khz::scene::test_scenes
