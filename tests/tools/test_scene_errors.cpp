// Malformed scene files: each is refused with a SceneError naming the file, the JSON path of the
// offending key, what was expected and what was found.
#include <khz/scene/read_scene.hpp>
#include <khz/scene/scene_error.hpp>
#include <khz/test/fixtures.hpp>

#include "scene_fixtures.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <functional>
#include <initializer_list>
#include <string>
#include <string_view>

namespace khz::scene {
namespace {

using Json = nlohmann::json;

SceneReadOptions test_options() {
  SceneReadOptions options = test_scenes::read_options();
  options.cgal_mesh_dir = test::cgal_mesh("dino.off").parent_path();
  return options;
}

using test_scenes::minimal_scene;

/// minimal_scene() with the wall a reduced model.
Json reduced_scene() {
  Json scene = minimal_scene();
  scene["objects"][1]["model"] = {
      {"type", "reduced"},
      {"material", {{"young_modulus", 1e6}, {"poisson_ratio", 0.45}, {"density", 1000}}}};
  return scene;
}

/// Succeeds if parsing `text` throws a SceneError at `path` whose message is `message` exactly.
::testing::AssertionResult text_fails_with(const std::string& text, std::string_view path,
                                           std::string_view message) {
  try {
    parse_scene(text, "scene.json", test_options());
  } catch (const SceneError& error) {
    const std::string expected_what =
        path.empty() ? "scene.json: " + std::string(message)
                     : "scene.json: " + std::string(path) + ": " + std::string(message);
    if (error.source() == "scene.json" && error.key_path() == path && error.message() == message &&
        error.what() == expected_what) {
      return ::testing::AssertionSuccess();
    }
    return ::testing::AssertionFailure()
           << "got      \"" << error.what() << "\"\nexpected \"" << expected_what << "\"";
  } catch (const std::exception& error) {
    return ::testing::AssertionFailure() << "threw another type: " << error.what();
  }
  return ::testing::AssertionFailure() << "did not throw";
}

::testing::AssertionResult fails_with(const Json& scene, std::string_view path,
                                      std::string_view message) {
  return text_fails_with(scene.dump(2), path, message);
}

/// minimal_scene() (or `base`) edited by `edit`.
Json edited(const std::function<void(Json&)>& edit, Json base = minimal_scene()) {
  edit(base);
  return base;
}

TEST(SceneErrors, JsonSyntax) {
  try {
    parse_scene("{\n  \"objects\": [\n    {\"name\": tru}\n  ]\n}\n", "scene.json");
    ADD_FAILURE() << "no error";
  } catch (const SceneError& error) {
    EXPECT_EQ(error.line(), 3);
    EXPECT_EQ(error.column(), 17);
    EXPECT_EQ(std::string(error.what()),
              "scene.json:3:17: JSON syntax error: syntax error while parsing value - invalid "
              "literal; last read: '\"name\": tru}'");
  }
  try {
    parse_scene("", "empty.json");
    ADD_FAILURE() << "no error";
  } catch (const SceneError& error) {
    EXPECT_EQ(std::string(error.what()),
              "empty.json:1:1: JSON syntax error: syntax error while parsing value - unexpected "
              "end of input; expected '[', '{', or a literal");
  }
  EXPECT_TRUE(text_fails_with(R"({"objects": [{"name": "a", "scale": 1e400}]})", "objects[0].scale",
                              "number out of range: number overflow parsing '1e400'"));
  EXPECT_TRUE(text_fails_with("[1, 2]", "", "expected an object {...}, got [1,2]"));
}

TEST(SceneErrors, DuplicateKeys) {
  EXPECT_TRUE(text_fails_with(R"({"objects": [{"name": "a"}, {"name": "b", "field": {"cells": 1,
                             "cells": 2}}]})",
                              "objects[1].field.cells",
                              "duplicate key: an object may name each key once"));
  EXPECT_TRUE(text_fails_with(R"({"loop": {}, "loop": {}})", "loop",
                              "duplicate key: an object may name each key once"));
}

TEST(SceneErrors, UnknownKeysSuggestTheClosestKnownOne) {
  EXPECT_TRUE(fails_with(edited(
                             [](Json& s) {
                               s["objects"][1]["model"]["meshing"] = {{"resoluton", 32}};
                             },
                             reduced_scene()),
                         "objects[1].model.meshing.resoluton",
                         "unknown key; did you mean \"resolution\"?"));
  EXPECT_TRUE(fails_with(edited([](Json& s) {
                           s["objects"][0]["centre"] = true;
                           s["objects"][0]["center"] = true;
                         }),
                         "objects[0].center", "unknown key; did you mean \"centre\"?"));
  // Not a typo, but the name of the same setting elsewhere.
  EXPECT_TRUE(fails_with(edited([](Json& s) {
                           s["objects"][1]["field"] = {{"resolution", 64}};
                         }),
                         "objects[1].field.resolution", "unknown key; did you mean \"cells\"?"));
  EXPECT_TRUE(fails_with(edited([](Json& s) {
                           s["objects"][1]["field"] = {{"resoluton", 64}};
                         }),
                         "objects[1].field.resoluton", "unknown key; did you mean \"cells\"?"));
  EXPECT_TRUE(fails_with(edited([](Json& s) {
                           s["loop"] = {{"period", 0.001}};
                         }),
                         "loop.period",
                         "unknown key; the keys here are cpu, duration, priority, rate_hz, "
                         "realtime_priority"));
  EXPECT_TRUE(fails_with(edited([](Json& s) {
                           s["coupling"] = {{"period", 0.001}};
                         }),
                         "coupling.period", "unknown key; did you mean \"loop.rate_hz\"?"));
}

TEST(SceneErrors, MissingRequiredKeys) {
  EXPECT_TRUE(fails_with(edited([](Json& s) { s["objects"][1].erase("mesh"); }), "objects[1]",
                         "missing required key \"mesh\" (the surface mesh file, or "
                         "\"cgal:NAME\")"));
  EXPECT_TRUE(fails_with(edited([](Json& s) { s.erase("haptic"); }), "",
                         "missing required key \"haptic\" (the held object and its grasp "
                         "point)"));
  EXPECT_TRUE(fails_with(edited([](Json& s) { s.erase("objects"); }), "",
                         "missing required key \"objects\" (the scene's objects)"));
  EXPECT_TRUE(
      fails_with(edited([](Json& s) { s["objects"][1]["model"]["material"].erase("density"); },
                        reduced_scene()),
                 "objects[1].model.material", "missing required key \"density\" (ρ in kg/m³)"));
  EXPECT_TRUE(fails_with(
      edited([](Json& s) { s["objects"][1]["model"].erase("material"); }, reduced_scene()),
      "objects[1].model",
      "missing required key \"material\" (young_modulus, poisson_ratio and "
      "density)"));
}

TEST(SceneErrors, WrongTypes) {
  EXPECT_TRUE(fails_with(edited([](Json& s) { s["objects"][0]["scale"] = "big"; }),
                         "objects[0].scale", "expected a number > 0, got \"big\""));
  EXPECT_TRUE(fails_with(edited([](Json& s) {
                           s["objects"][1]["field"] = {{"cells", 2.5}};
                         }),
                         "objects[1].field.cells", "expected an integer in [1, 32768], got 2.5"));
  EXPECT_TRUE(fails_with(edited([](Json& s) { s["objects"][0]["centre"] = "yes"; }),
                         "objects[0].centre", "expected true or false, got \"yes\""));
  EXPECT_TRUE(fails_with(edited([](Json& s) {
                           s["objects"][0]["pose"] = {{"position", {1, 2}}};
                         }),
                         "objects[0].pose.position",
                         "expected an array of 3 numbers [x, y, z], got [1,2]"));
  EXPECT_TRUE(fails_with(edited([](Json& s) { s["objects"] = Json::object(); }), "objects",
                         "expected a non-empty array of objects [{...}], got {}"));
  EXPECT_TRUE(fails_with(edited([](Json& s) { s["contact"] = 5; }), "contact",
                         "expected an object {...}, got 5"));
  EXPECT_TRUE(fails_with(edited([](Json& s) { s["objects"][0]["name"] = ""; }), "objects[0].name",
                         "expected a non-empty string, got \"\""));
  EXPECT_TRUE(fails_with(edited([](Json& s) { s["version"] = 3; }), "version",
                         "expected 1 or 2 (the scene format versions so far), got 3"));
}

TEST(SceneErrors, NumbersOutOfRange) {
  EXPECT_TRUE(
      fails_with(edited(
                     [](Json& s) {
                       s["objects"][1]["model"]["basis"] = {{"method", "sketch"}, {"r", -3}};
                       s["objects"][1]["model"]["anchors"] =
                           Json::parse(R"([{"type": "box", "min": [0,0,0], "max": [1,1,1]}])");
                     },
                     reduced_scene()),
                 "objects[1].model.basis.r", "expected an integer ≥ 1, got -3"));
  EXPECT_TRUE(fails_with(edited(
                             [](Json& s) {
                               s["objects"][1]["model"]["basis"] = {{"k", 4}, {"r", 40}};
                             },
                             reduced_scene()),
                         "objects[1].model.basis.r",
                         "expected an integer in [1, 20] (k + k² for k = 4 without anchors), "
                         "got 40"));
  EXPECT_TRUE(fails_with(
      edited(
          [](Json& s) {
            s["objects"][1]["model"]["basis"] = {{"k", 4}, {"r", 5}, {"modal_derivatives", false}};
          },
          reduced_scene()),
      "objects[1].model.basis.r",
      "expected an integer in [1, 4] (at most k = 4 without modal "
      "derivatives), got 5"));
  EXPECT_TRUE(fails_with(
      edited([](Json& s) { s["objects"][1]["model"]["material"]["poisson_ratio"] = 0.5; },
             reduced_scene()),
      "objects[1].model.material.poisson_ratio", "expected a number in (-1, 0.5), got 0.5"));
  EXPECT_TRUE(fails_with(edited([](Json& s) {
                           s["objects"][1]["field"] = {{"cells", 0}};
                         }),
                         "objects[1].field.cells", "expected an integer in [1, 32768], got 0"));
  EXPECT_TRUE(fails_with(edited([](Json& s) {
                           s["objects"][1]["field"] = {{"exact_band", 1}};
                         }),
                         "objects[1].field.exact_band",
                         "expected a number ≥ √3 ≈ 1.732 (cell spacings), got 1"));
  EXPECT_TRUE(fails_with(edited([](Json& s) {
                           s["coupling"] = {{"static_damping", 1}};
                         }),
                         "coupling.static_damping", "expected a number in [0, 1), got 1"));
  EXPECT_TRUE(fails_with(edited([](Json& s) {
                           s["loop"] = {{"rate_hz", 0}};
                         }),
                         "loop.rate_hz", "expected a number in (0, 100000], got 0"));
  EXPECT_TRUE(fails_with(edited([](Json& s) {
                           s["objects"][0]["pointshell"] = {{"levels", 3e9}};
                         }),
                         "objects[0].pointshell.levels",
                         "expected an integer ≥ 1, got 3000000000.0 (outside [-2147483648, "
                         "2147483647])"));
  EXPECT_TRUE(
      fails_with(edited([](Json& s) {
                   s["objects"][0]["pointshell"] = {{"first_level_points", 1000}, {"levels", 14}};
                 }),
                 "objects[0].pointshell.first_level_points",
                 "n₀(4ᴸ − 1)/3 = 89478485000 points for n₀ = 1000 and L = 14: expected "
                 "at most 2147483647 points in all"));
  EXPECT_TRUE(fails_with(edited(
                             [](Json& s) {
                               s["objects"][1]["field"] = {{"proxies", 4}, {"neighbours", 6}};
                             },
                             reduced_scene()),
                         "objects[1].field.proxies",
                         "expected an integer ≥ neighbours (6), got 4"));
  EXPECT_TRUE(fails_with(edited([](Json& s) {
                           s["coupling"] = {{"stiffness", 4000}, {"device_max_stiffness", 3000}};
                         }),
                         "coupling.stiffness",
                         "expected at most device_max_stiffness = 3000 N/m (k_VC bounds the "
                         "stiffness the device renders, thesis §4.7), got 4000"));
  EXPECT_TRUE(fails_with(edited([](Json& s) { s["threads"] = 0; }), "threads",
                         "expected an integer ≥ 1, got 0"));
}

TEST(SceneErrors, ChoicesAndSettingsOfAnotherChoice) {
  EXPECT_TRUE(fails_with(edited([](Json& s) {
                           s["contact"] = {{"degradation", {{"mode", "nodes"}}}};
                         }),
                         "contact.degradation.mode",
                         "expected one of \"none\", \"node_count\" or \"time_budget\", got "
                         "\"nodes\""));
  EXPECT_TRUE(fails_with(edited([](Json& s) { s["objects"][0]["roles"] = {"pointshel"}; }),
                         "objects[0].roles[0]",
                         "expected one of \"pointshell\" or \"distance_field\", got "
                         "\"pointshel\"; did you mean \"pointshell\"?"));
  EXPECT_TRUE(fails_with(edited([](Json& s) {
                           s["contact"] = {{"degradation", {{"budget_microseconds", 100}}}};
                         }),
                         "contact.degradation.budget_microseconds",
                         "applies only to mode \"time_budget\" (mode is \"none\")"));
  EXPECT_TRUE(fails_with(
      edited(
          [](Json& s) {
            s["objects"][1]["model"]["meshing"] = {{"method", "tetrahedra"}, {"resolution", 32}};
          },
          reduced_scene()),
      "objects[1].model.meshing.resolution",
      "applies only to method \"voxels\" (method is \"tetrahedra\")"));
  EXPECT_TRUE(fails_with(edited([](Json& s) {
                           s["objects"][0]["pointshell"] = {{"method", "repulsion"}, {"growth", 4}};
                         }),
                         "objects[0].pointshell.growth",
                         "applies only to the methods \"vertices\", \"random\" and \"voxels\" "
                         "(repulsion's levels grow by 4)"));
  EXPECT_TRUE(fails_with(edited([](Json& s) {
                           s["objects"][0]["pointshell"] = {{"method", "random"}};
                         }),
                         "objects[0].pointshell",
                         "missing required key \"points\" (the number of random samples)"));
  EXPECT_TRUE(fails_with(edited([](Json& s) {
                           s["contact"] = {{"coherence", {{"max_translation", 0.001}}}};
                         }),
                         "contact.coherence.max_translation",
                         "applies only to enabled temporal coherence (\"enabled\": true)"));
  EXPECT_TRUE(fails_with(edited([](Json& s) {
                           s["device"] = {{"type", "null"}, {"file", "press.csv"}};
                         }),
                         "device.file", "applies only to type \"trajectory\" (type is \"null\")"));
  EXPECT_TRUE(fails_with(edited([](Json& s) {
                           s["objects"][1]["field"] = {{"offset", 0.01}};
                         }),
                         "objects[1].field.offset",
                         "applies only to polygon soups (\"soup\": true)"));
  EXPECT_TRUE(fails_with(edited([](Json& s) {
                           s["objects"][0]["scale"] = 2;
                           s["objects"][0]["size"] = 0.1;
                         }),
                         "objects[0].size", "give either \"scale\" or \"size\", not both"));
}

TEST(SceneErrors, Friction) {
  EXPECT_TRUE(fails_with(edited([](Json& s) {
                           s["contact"] = {{"friction", {{"static", 0.2}, {"kinetic", 0.3}}}};
                         }),
                         "contact.friction.kinetic",
                         "expected at most static = 0.2 (a sliding contact pulls no harder than "
                         "a stuck one holds), got 0.3"));
  EXPECT_TRUE(fails_with(edited([](Json& s) {
                           s["contact"] = {{"friction", {{"static", -0.2}}}};
                         }),
                         "contact.friction.static", "expected a number ≥ 0, got -0.2"));
  EXPECT_TRUE(fails_with(edited([](Json& s) {
                           s["contact"] = {{"friction", {{"mu_s", 0.2}}}};
                         }),
                         "contact.friction.mu_s", "unknown key; did you mean \"static\"?"));
  EXPECT_TRUE(fails_with(edited([](Json& s) {
                           s["contact"] = {{"onset_voxels", -0.1}};
                         }),
                         "contact.onset_voxels", "expected a number ≥ 0, got -0.1"));
  // Two hands: the tool and the ball (pointshells), the wall and the floor fixed (fields).
  const auto pairs = [](Json entries) {
    return edited([&](Json& s) {
      s["version"] = 2;
      s["objects"].push_back(
          {{"name", "floor"}, {"mesh", "cube.off"}, {"roles", {"distance_field"}}});
      s["objects"].push_back({{"name", "ball"}, {"mesh", "cube.off"}, {"roles", {"pointshell"}}});
      s["haptic"] = Json::parse(R"([{"object": "tool"}, {"object": "ball"}])");
      s["contact"] = {{"pairs", entries}};
    });
  };
  EXPECT_TRUE(fails_with(pairs(Json::parse(R"([{"objects": ["tool"]}])")),
                         "contact.pairs[0].objects",
                         "expected two object names [\"a\", \"b\"], got [\"tool\"]"));
  EXPECT_TRUE(fails_with(pairs(Json::parse(R"([{"objects": ["tool", "walls"]}])")),
                         "contact.pairs[0].objects[1]",
                         "no object is named \"walls\"; did you mean \"wall\"?"));
  EXPECT_TRUE(fails_with(pairs(Json::parse(R"([{"objects": ["wall", "wall"]}])")),
                         "contact.pairs[0].objects", "names \"wall\" twice"));
  EXPECT_TRUE(fails_with(pairs(Json::parse(R"([{"objects": ["wall", "floor"]}])")),
                         "contact.pairs[0].objects",
                         "neither \"wall\" nor \"floor\" moves (held or free), and fixed objects "
                         "do not touch each other"));
  EXPECT_TRUE(fails_with(pairs(Json::parse(R"([{"objects": ["tool", "ball"]}])")),
                         "contact.pairs[0].objects",
                         "\"tool\" (\"pointshell\") and \"ball\" (\"pointshell\") never touch: one "
                         "needs the pointshell role and the other the distance_field role"));
  EXPECT_TRUE(fails_with(
      pairs(Json::parse(R"([{"objects": ["tool", "wall"]}, {"objects": ["wall", "tool"]}])")),
      "contact.pairs[1].objects", "this pair is contact.pairs[0] already; give each pair once"));
  EXPECT_TRUE(fails_with(
      pairs(Json::parse(R"([{"objects": ["tool", "wall"], "friction": {"kinetic": 0.1}}])")),
      "contact.pairs[0].friction.kinetic",
      "expected at most static = 0 (a sliding contact pulls no harder than a "
      "stuck one holds), got 0.1"));
}

TEST(SceneErrors, ObjectsAndRoles) {
  EXPECT_TRUE(fails_with(edited([](Json& s) { s["objects"][1]["name"] = "tool"; }),
                         "objects[1].name",
                         "duplicate object name \"tool\" (objects[0] has it too)"));
  EXPECT_TRUE(fails_with(edited([](Json& s) { s["objects"][1]["name"] = "my wall"; }),
                         "objects[1].name",
                         "expected a name of letters, digits, '_', '-' and '.' not starting with "
                         "'.', got \"my wall\""));
  EXPECT_TRUE(fails_with(edited([](Json& s) { s["objects"][1]["roles"] = Json::array(); }),
                         "objects[1].roles",
                         "an object needs a role: expected \"pointshell\", \"distance_field\" or "
                         "both, got []"));
  EXPECT_TRUE(fails_with(edited([](Json& s) {
                           s["objects"][1]["roles"] = {"distance_field", "distance_field"};
                         }),
                         "objects[1].roles[1]", "duplicate role \"distance_field\""));
  EXPECT_TRUE(fails_with(edited([](Json& s) {
                           s["objects"][1]["pointshell"] = {{"levels", 3}};
                         }),
                         "objects[1].pointshell",
                         "pointshell settings on an object without the \"pointshell\" role"));
  EXPECT_TRUE(fails_with(edited([](Json& s) {
                           s["objects"][0]["pointshell"] = {{"method", "vertices"}};
                           s["objects"][0]["field"] = {{"cells", 64}};
                         }),
                         "objects[0].field",
                         "field settings on an object that has no distance field: it has no "
                         "\"distance_field\" role and no repulsion pointshell"));
  EXPECT_TRUE(fails_with(edited([](Json& s) {
                           s["objects"][1]["field"] = {{"proxies", 30}};
                         }),
                         "objects[1].field.proxies",
                         "applies only to a reduced object with the distance_field role (its "
                         "deformed field's proxies)"));
}

TEST(SceneErrors, TheHeldObject) {
  EXPECT_TRUE(fails_with(edited([](Json& s) { s["haptic"]["object"] = "tol"; }), "haptic.object",
                         "no object is named \"tol\"; did you mean \"tool\"?"));
  EXPECT_TRUE(fails_with(edited([](Json& s) { s["haptic"]["object"] = "hammer"; }), "haptic.object",
                         "no object is named \"hammer\" (the objects are \"tool\", \"wall\")"));
  EXPECT_TRUE(fails_with(edited([](Json& s) { s["haptic"]["role"] = "distance_field"; }),
                         "haptic.role",
                         "object \"tool\" (objects[0]) has no \"distance_field\" role (its roles: "
                         "\"pointshell\")"));
  EXPECT_TRUE(fails_with(edited([](Json& s) { s["objects"][1]["roles"] = {"pointshell"}; }),
                         "objects[1].roles",
                         "object \"wall\" touches nothing: the held object \"tool\" plays "
                         "\"pointshell\", so the other objects need the \"distance_field\" role"));
  EXPECT_TRUE(fails_with(edited([](Json& s) { s["objects"].erase(1); }), "haptic.object",
                         "the held object \"tool\" (objects[0]) plays \"pointshell\", but there is "
                         "no other object with the \"distance_field\" role for it to touch"));
  EXPECT_TRUE(fails_with(edited([](Json& s) { s["haptic"]["grasp_point"] = "center"; }),
                         "haptic.grasp_point",
                         "expected \"centre\", got \"center\"; did you mean \"centre\"?"));
}

// Free bodies ("dynamics"), their settings ("dynamics" at the top level) and grasping.
TEST(SceneErrors, FreeBodiesAndGrasping) {
  // The tool held, the wall fixed, a free box with both roles.
  const auto with_box = [](const std::function<void(Json&)>& edit) {
    return edited([&](Json& s) {
      s["objects"].push_back({{"name", "box"},
                              {"mesh", "cube.off"},
                              {"roles", {"pointshell", "distance_field"}},
                              {"dynamics", {{"mass", 0.5}}}});
      edit(s);
    });
  };
  EXPECT_NO_THROW(parse_scene(with_box([](Json&) {}).dump(), "scene.json", test_options()));
  EXPECT_TRUE(fails_with(with_box([](Json& s) { s["objects"][2]["dynamics"]["mass"] = 0; }),
                         "objects[2].dynamics.mass", "expected a number > 0, got 0"));
  EXPECT_TRUE(fails_with(with_box([](Json& s) { s["objects"][2]["dynamics"]["density"] = 800; }),
                         "objects[2].dynamics.mass",
                         "give either \"density\" or \"mass\", not both"));
  EXPECT_TRUE(fails_with(with_box([](Json& s) {
                           s["objects"][2]["dynamics"]["velocity"] = {1, 2};
                         }),
                         "objects[2].dynamics.velocity",
                         "expected an array of 3 numbers [x, y, z], got [1,2]"));
  EXPECT_TRUE(fails_with(with_box([](Json& s) { s["objects"][2]["mass"] = 0.5; }),
                         "objects[2].mass", "unknown key; did you mean \"dynamics\"?"));
  EXPECT_TRUE(fails_with(
      with_box([](Json& s) {
        s["objects"][2]["model"] = {
            {"type", "reduced"},
            {"material", {{"young_modulus", 1e6}, {"poisson_ratio", 0.45}, {"density", 1000}}}};
      }),
      "objects[2].dynamics",
      "a free body is rigid, but model.type is \"reduced\"; remove \"model\" "
      "or \"dynamics\""));
  EXPECT_TRUE(fails_with(with_box([](Json& s) { s["haptic"]["object"] = "box"; }), "haptic.object",
                         "object \"box\" (objects[2]) is a free body (it has \"dynamics\"): a "
                         "hand holds an object without dynamics, and picks a free one up with its "
                         "grasp_button"));
  // A free body with only a distance field touches the held tool's pointshell.
  EXPECT_NO_THROW(
      parse_scene(with_box([](Json& s) { s["objects"][2]["roles"] = {"distance_field"}; }).dump(),
                  "scene.json", test_options()));
  // Top-level "dynamics": only with a free body; time_step is the loop's.
  EXPECT_TRUE(fails_with(edited([](Json& s) {
                           s["dynamics"] = {{"gravity", {0, 0, -9.81}}};
                         }),
                         "dynamics",
                         "settings for free bodies, but no object has \"dynamics\" "
                         "(objects[i].dynamics makes one)"));
  EXPECT_TRUE(fails_with(with_box([](Json& s) {
                           s["dynamics"] = {{"time_step", 0.001}};
                         }),
                         "dynamics.time_step", "unknown key; did you mean \"loop.rate_hz\"?"));
  EXPECT_TRUE(fails_with(with_box([](Json& s) {
                           s["dynamics"] = {{"sleep_time", -1}};
                         }),
                         "dynamics.sleep_time", "expected a number ≥ 0, got -1"));
  EXPECT_TRUE(fails_with(with_box([](Json& s) {
                           s["gravity"] = {0, 0, -9.81};
                         }),
                         "gravity", "unknown key; did you mean \"dynamics\"?"));
  // The grasp button.
  EXPECT_TRUE(fails_with(with_box([](Json& s) { s["haptic"]["grasp_button"] = 32; }),
                         "haptic.grasp_button",
                         "expected -1 (none) or a button index in [0, 31], got 32"));
  EXPECT_TRUE(fails_with(with_box([](Json& s) {
                           s["haptic"]["grasp_button"] = 1;
                           s["device"] = {{"safety", {{"index_button", 1}}}};
                         }),
                         "haptic.grasp_button",
                         "button 1 is the device's safety.index_button already; choose another"));
  EXPECT_TRUE(fails_with(
      with_box([](Json& s) {
        s["device"] = {{"type", "operator"},
                       {"keyframes", {{{"time", 0}, {"position", {0, 0, 0}}, {"buttons", -1}}}}};
      }),
      "device.keyframes[0].buttons", "expected a bitmask in [0, 2^32), got -1"));
}

/// minimal_scene() with its hand as a one-entry list (version 2) and the top-level device moved
/// into it.
Json two_hand_base() {
  Json scene = minimal_scene();
  scene["objects"][1]["roles"] = {"distance_field", "pointshell"};
  scene["haptic"] = Json::array({{{"object", "tool"}, {"device", {{"type", "null"}}}},
                                 {{"object", "wall"}, {"role", "distance_field"}}});
  return scene;
}

TEST(SceneErrors, SeveralHands) {
  EXPECT_TRUE(fails_with(edited([](Json& s) { s["version"] = 1; }, two_hand_base()), "haptic",
                         "a list of held objects needs \"version\": 2 (version 1 holds one "
                         "object: \"haptic\": {\"object\": ...})"));
  EXPECT_TRUE(fails_with(edited([](Json& s) { s["haptic"] = Json::array(); }), "haptic",
                         "expected at least one held object [{\"object\": ...}, ...], got []"));
  EXPECT_TRUE(fails_with(edited(
                             [](Json& s) {
                               s["device"] = {{"type", "null"}};
                             },
                             two_hand_base()),
                         "device",
                         "with \"haptic\" as a list, each hand names its own device: move "
                         "this block into haptic[i].device"));
  EXPECT_TRUE(fails_with(edited(
                             [](Json& s) {
                               s["haptic"][1]["object"] = "tool";
                               s["haptic"][1].erase("role");
                             },
                             two_hand_base()),
                         "haptic[1].object",
                         "object \"tool\" is held by haptic[0] already; a hand holds an object "
                         "of its own"));
  EXPECT_TRUE(fails_with(edited(
                             [](Json& s) {
                               s["haptic"][1]["device"] = {{"type", "robot"}};
                             },
                             two_hand_base()),
                         "haptic[1].device.type",
                         "expected one of \"null\", \"trajectory\", \"operator\" or "
                         "\"hardware\", got \"robot\""));
  EXPECT_TRUE(fails_with(
      edited([](Json& s) { s["haptic"][0]["devise"] = Json::object(); }, two_hand_base()),
      "haptic[0].devise", "unknown key; did you mean \"device\"?"));
  // A held object only another held object could touch is fine; one nothing can touch is not.
  EXPECT_TRUE(fails_with(
      edited([](Json& s) { s["objects"][1]["roles"] = {"pointshell"}; }, two_hand_base()),
      "haptic[1].role",
      "object \"wall\" (objects[1]) has no \"distance_field\" role (its "
      "roles: \"pointshell\")"));
  EXPECT_TRUE(fails_with(edited(
                             [](Json& s) {
                               s["objects"][1]["roles"] = {"pointshell"};
                               s["haptic"][1].erase("role");
                             },
                             two_hand_base()),
                         "haptic[0].object",
                         "the held object \"tool\" (objects[0]) plays \"pointshell\", but "
                         "there is no other object with the \"distance_field\" role for it to "
                         "touch"));
}

TEST(SceneErrors, ReducedModelSettings) {
  EXPECT_TRUE(fails_with(edited([](Json& s) {
                           s["objects"][1]["model"] = {{"basis", {{"k", 5}}}};
                         }),
                         "objects[1].model.basis",
                         "reduced-model settings on a rigid object (model.type is \"rigid\" by "
                         "default); set \"type\": \"reduced\" or remove this key"));
  EXPECT_TRUE(
      fails_with(edited([](Json& s) {
                   s["objects"][1]["model"] = {{"type", "rigid"}, {"anchors", Json::array()}};
                 }),
                 "objects[1].model.anchors",
                 "reduced-model settings on a rigid object (model.type is \"rigid\"); set "
                 "\"type\": \"reduced\" or remove this key"));
  EXPECT_TRUE(fails_with(edited(
                             [](Json& s) {
                               s["objects"][1]["model"]["basis"] = {
                                   {"method", "sketch"}, {"r", 3}, {"loads", "loads.csv"}};
                             },
                             reduced_scene()),
                         "objects[1].model.basis.method",
                         "a sketch basis needs anchors (model.anchors): its static solves need "
                         "the rigid motions removed"));
  EXPECT_TRUE(fails_with(edited(
                             [](Json& s) {
                               s["objects"][1]["model"]["anchors"] = Json::parse(
                                   R"([{"type": "box", "min": [0, 0, 0], "max": [1, -1, 1]}])");
                             },
                             reduced_scene()),
                         "objects[1].model.anchors[0].max",
                         "expected a corner ≥ min [0,0,0] in every coordinate, got [1,-1,1]"));
  EXPECT_TRUE(fails_with(
      edited(
          [](Json& s) {
            s["objects"][1]["model"]["anchors"] =
                Json::parse(R"([{"type": "half_space", "point": [0, 0, 0], "normal": [0, 0, 0]}])");
          },
          reduced_scene()),
      "objects[1].model.anchors[0].normal", "expected a non-zero normal, got [0,0,0]"));
  EXPECT_TRUE(fails_with(edited(
                             [](Json& s) {
                               s["objects"][1]["field"] = {{"soup", true}};
                               s["objects"][1]["model"]["meshing"] = {{"method", "tetrahedra"}};
                             },
                             reduced_scene()),
                         "objects[1].model.meshing.method",
                         "\"tetrahedra\" needs a closed surface, but field.soup says the mesh is "
                         "a polygon soup; use \"voxels\""));
}

TEST(SceneErrors, FilesThatDoNotExist) {
  const std::string directory = test::test_file("scenes").lexically_normal().string();
  EXPECT_TRUE(fails_with(edited([](Json& s) { s["objects"][1]["mesh"] = "meshes/wall.off"; }),
                         "objects[1].mesh",
                         "mesh file not found: " + directory +
                             "/meshes/wall.off (from "
                             "\"meshes/wall.off\" relative to " +
                             directory + ")"));
  EXPECT_TRUE(fails_with(
      edited([](Json& s) { s["objects"][1]["mesh"] = "cgal:wall.off"; }), "objects[1].mesh",
      "mesh file not found: " + test::cgal_mesh("dino.off").parent_path().string() +
          "/wall.off (CGAL's demo mesh \"wall.off\" in " +
          test::cgal_mesh("dino.off").parent_path().string() + ")"));
  EXPECT_TRUE(fails_with(edited([](Json& s) { s["objects"][1]["mesh"] = "cgal:../dino.off"; }),
                         "objects[1].mesh",
                         "expected \"cgal:NAME\" with NAME one of CGAL's demo meshes, e.g. "
                         "\"cgal:dino.off\", got \"cgal:../dino.off\""));
  EXPECT_TRUE(fails_with(edited([](Json& s) { s["objects"][1]["mesh"] = "wall.vtk"; }),
                         "objects[1].mesh",
                         "expected a surface mesh file (.obj, .off, .stl or .ply), got "
                         "\"wall.vtk\""));
  EXPECT_TRUE(fails_with(edited([](Json& s) {
                           s["device"] = {{"type", "trajectory"}, {"file", "gone.csv"}};
                         }),
                         "device.file",
                         "trajectory file not found: " + directory +
                             "/gone.csv (from "
                             "\"gone.csv\" relative to " +
                             directory + ")"));
}

TEST(SceneErrors, ProceduralShapes) {
  EXPECT_TRUE(
      fails_with(edited([](Json& s) { s["objects"][1]["mesh"] = "shape:cube"; }), "objects[1].mesh",
                 "unknown shape \"cube\"; the shapes are alpha_tube, peg, plate_with_hole"));
  EXPECT_TRUE(fails_with(edited([](Json& s) { s["objects"][1]["mesh"] = "shape:"; }),
                         "objects[1].mesh",
                         "unknown shape \"\"; the shapes are alpha_tube, peg, plate_with_hole"));
  EXPECT_TRUE(fails_with(edited([](Json& s) { s["objects"][1]["mesh"] = "shape:peg:side=0"; }),
                         "objects[1].mesh", "shape \"peg\": side: expected a number > 0, got 0"));
  EXPECT_TRUE(fails_with(
      edited([](Json& s) { s["objects"][0]["mesh"] = "shape:alpha_tube:segment=64"; }),
      "objects[0].mesh",
      "shape \"alpha_tube\": unknown parameter \"segment\"; did you mean \"segments\"? The "
      "parameters are loop, radius, segments, sides"));
  // No file, so no extension to check and nothing to find, even with check_files.
  EXPECT_NO_THROW(
      parse_scene(edited([](Json& s) { s["objects"][1]["mesh"] = "shape:plate_with_hole"; }).dump(),
                  "scene.json", test_options()));
}

TEST(SceneErrors, Devices) {
  EXPECT_TRUE(fails_with(edited([](Json& s) {
                           s["device"] = Json::parse(R"({"type": "operator", "keyframes": [
                               {"time": 0, "position": [0, 0, 0]},
                               {"time": 0.5, "position": [0, 0, 0.01]},
                               {"time": 0.5, "position": [0, 0, 0.02]}]})");
                         }),
                         "device.keyframes[2].time",
                         "expected a time after keyframes[1].time = 0.5 s, got 0.5"));
  EXPECT_TRUE(fails_with(edited([](Json& s) {
                           s["device"] = {{"type", "operator"}, {"keyframes", Json::array()}};
                         }),
                         "device.keyframes",
                         "expected a non-empty array of keyframes [{\"time\", \"position\", "
                         "\"rotation\"}], got []"));
  EXPECT_TRUE(fails_with(
      edited([](Json& s) {
        s["device"] = {{"type", "hardware"}, {"name", "dhd"}, {"capabilities", {{"max_force", 5}}}};
      }),
      "device.capabilities",
      "applies only to the null, trajectory and operator devices (a hardware "
      "device reports its own)"));
  EXPECT_TRUE(fails_with(edited([](Json& s) {
                           s["device"] = {{"capabilities", {{"workspace_max", {0.1, 0.1, -0.2}}}}};
                         }),
                         "device.capabilities.workspace_max",
                         "expected workspace_min < workspace_max in every coordinate, got [-0.1, "
                         "-0.1, -0.1] and [0.1, 0.1, -0.2]"));
  // The operator's stability is the library's check, reported at the device.
  try {
    parse_scene(edited([](Json& s) {
                  s["device"] = Json::parse(R"({"type": "operator", "substeps": 1,
                      "keyframes": [{"time": 0, "position": [0, 0, 0]}],
                      "hand": {"stiffness": 1e9}})");
                }).dump(),
                "scene.json", test_options());
    ADD_FAILURE() << "no error";
  } catch (const SceneError& error) {
    EXPECT_EQ(error.key_path(), "device");
    EXPECT_EQ(
        error.message().rfind("the simulated operator cannot run at loop.rate_hz = 1000 Hz: ", 0),
        0u)
        << error.message();
  }
}

}  // namespace
}  // namespace khz::scene
