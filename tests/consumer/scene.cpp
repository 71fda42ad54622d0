// Links only Kilohertz::scene from an install prefix: a scene described in JSON (procedural
// meshes, so no data files), prepared through a product cache and run as a haptic::World in
// simulated time. A peg stands 1 mm deep on a plate; a null device holds it 2 mm deeper still,
// so the plate pushes it up.
#include <khz/scene/prepare_scene.hpp>
#include <khz/scene/read_scene.hpp>
#include <khz/scene/scene_runtime.hpp>
#include <khz/scene/version.hpp>

#include <cstring>
#include <filesystem>
#include <iostream>

int main() {
  if (std::strcmp(khz::scene::library_version(), KHZ_SCENE_VERSION_STRING) != 0) {
    std::cerr << "libkhz_scene " << khz::scene::library_version() << " differs from its headers' "
              << KHZ_SCENE_VERSION_STRING << "\n";
    return 1;
  }
  const khz::scene::SceneDescription description = khz::scene::parse_scene(R"({
    "objects": [
      {"name": "plate", "mesh": "shape:plate_with_hole", "roles": ["distance_field"],
       "field": {"cells": 32}},
      {"name": "peg", "mesh": "shape:peg", "pose": {"position": [0.03, 0, -0.001]},
       "roles": ["pointshell"],
       "pointshell": {"method": "repulsion", "first_level_points": 16, "levels": 3}}
    ],
    "haptic": {"object": "peg"},
    "device": {"type": "null", "pose": {"position": [0.03, 0, 0.037]}},
    "loop": {"rate_hz": 1000, "duration": 0.2}
  })",
                                                                           "consumer scene");
  khz::scene::ProductCache cache(std::filesystem::temp_directory_path() / "khz_consumer_cache");
  const khz::scene::PreparedScene prepared = khz::scene::prepare_scene(description, cache);

  khz::scene::SceneRuntime runtime(prepared);
  runtime.open_devices();
  double force_up = 0.0;
  for (int i = 0; i < 200; ++i) {
    const double t = 1e-3 * i;
    force_up = runtime.world().cycle(t, t + 1e-3, [t] { return t; }).front().contact.force.z();
  }
  runtime.close_devices();
  if (!(force_up > 0.0)) {
    std::cerr << "installed libscene's runtime did not push the peg out of the plate\n";
    return 1;
  }
  std::cout << "Kilohertz::scene " << khz::scene::library_version() << ": the plate pushes the peg "
            << force_up << " N up\n";
  return 0;
}
