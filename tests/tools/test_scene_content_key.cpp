// Content keys: a product's key changes with exactly the inputs that determine the product, so a
// cache reuses products across scenes that differ only in something else.
#include <khz/scene/content_key.hpp>
#include <khz/scene/read_scene.hpp>
#include <khz/test/data_paths.hpp>
#include <khz/test/fixtures.hpp>

#include "scene_fixtures.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <string_view>
#include <utility>

namespace khz::scene {
namespace {

using Json = nlohmann::json;

SceneReadOptions test_options() { return test_scenes::read_options(); }

/// A reduced "tool" (pointshell and distance field, anchored) held against a rigid "wall".
Json base_scene() {
  return Json::parse(R"({
    "objects": [
      {
        "name": "tool", "mesh": "cube.off", "roles": ["pointshell", "distance_field"],
        "model": {
          "type": "reduced",
          "material": {"young_modulus": 1e6, "poisson_ratio": 0.45, "density": 1000},
          "anchors": [{"type": "box", "min": [0, 0, 0], "max": [1, 1, 0.1]}]
        }
      },
      {"name": "wall", "mesh": "cube.off", "roles": ["pointshell", "distance_field"]}
    ],
    "haptic": {"object": "tool"}
  })");
}

ObjectDescription tool_of(const Json& scene) {
  return parse_scene(scene.dump(), "scene.json", test_options()).objects[0];
}

/// The key of the tool's `product` in base_scene() edited by `edit`.
std::string key_after(const std::function<void(Json&)>& edit, Product product) {
  Json scene = base_scene();
  edit(scene);
  return content_key(tool_of(scene), product);
}

std::string base_key(Product product) { return content_key(tool_of(base_scene()), product); }

const Product all_products[] = {Product::distance_field, Product::pointshell,
                                Product::reduced_model};

TEST(SceneContentKey, IsCanonicalJson) {
  const std::string key = base_key(Product::distance_field);
  const Json parsed = Json::parse(key);
  EXPECT_EQ(parsed.dump(), key);  // sorted keys, no spaces
  EXPECT_EQ(parsed["key_version"], 1);
  EXPECT_EQ(parsed["product"], "distance_field");
  EXPECT_EQ(parsed["field"]["cells"], 128);
  EXPECT_EQ(parsed["mesh"]["xxh3"], file_hash_hex(test::test_file("scenes/cube.off")));
  EXPECT_EQ(parsed["mesh"]["extension"], ".off");
  EXPECT_EQ(key.find("cube.off"), std::string::npos) << "paths must not enter keys: " << key;
}

TEST(SceneContentKey, UnrelatedSettingsKeepEveryKey) {
  const std::function<void(Json&)> unrelated[] = {
      [](Json& s) {
        s["objects"][0]["name"] = "renamed";
        s["haptic"]["object"] = "renamed";
      },
      [](Json& s) {
        s["objects"][0]["pose"] = {{"position", {1, 2, 3}}};
      },
      [](Json& s) {
        s["objects"][1]["field"] = {{"cells", 32}};
      },  // the other object
      [](Json& s) {
        s["contact"] = {{"stiffness", 5000}};
      },
      [](Json& s) {
        s["coupling"] = {{"stiffness", 100}};
      },
      [](Json& s) {
        s["loop"] = {{"rate_hz", 2000}, {"duration", 3}};
      },
      [](Json& s) {
        s["device"] = {{"type", "hardware"}, {"name", "dhd"}};
      },
      [](Json& s) {
        s["haptic"]["grasp_point"] = {0, 0, 1};
      },
      [](Json& s) {
        s["objects"][0]["model"]["integrator"] = {{"mass_damping", 3}, {"time_step", 0.002}};
      },
      // Defaults written out are the defaults left out; 1 is 1.0.
      [](Json& s) {
        s["objects"][0]["scale"] = 1.0;
        s["objects"][0]["field"] = {{"cells", 128}, {"box_expansion", 1.5}};
        s["objects"][0]["pointshell"] = {{"method", "repulsion"}, {"levels", 4}};
        s["objects"][0]["model"]["basis"] = {{"method", "modes"}, {"k", 20}, {"r", 30.0}};
        s["objects"][0]["model"]["meshing"] = {{"method", "voxels"}, {"resolution", 64}};
      },
  };
  for (const Product product : all_products) {
    SCOPED_TRACE(std::string(product_name(product)));
    const std::string base = base_key(product);
    for (std::size_t i = 0; i < std::size(unrelated); ++i) {
      EXPECT_EQ(key_after(unrelated[i], product), base) << "edit " << i;
    }
  }
}

TEST(SceneContentKey, EachProductFollowsItsOwnInputs) {
  struct Edit {
    const char* what;
    std::function<void(Json&)> edit;
    bool field, shell, model;  // which keys must change
  };
  const Edit edits[] = {
      {"scale", [](Json& s) { s["objects"][0]["scale"] = 2; }, true, true, true},
      {"size", [](Json& s) { s["objects"][0]["size"] = 1; }, true, true, true},
      {"centre", [](Json& s) { s["objects"][0]["centre"] = true; }, true, true, true},
      {"field cells",
       [](Json& s) {
         s["objects"][0]["field"] = {{"cells", 64}};
       },
       true, true, false},
      {"soup offset",
       [](Json& s) {
         s["objects"][0]["field"] = {{"soup", true}, {"offset", 0.02}};
       },
       true, true, false},
      {"proxies",
       [](Json& s) {
         s["objects"][0]["field"] = {{"proxies", 50}};
       },
       false, false, false},
      {"pointshell levels",
       [](Json& s) {
         s["objects"][0]["pointshell"] = {{"levels", 3}};
       },
       false, true, false},
      {"pointshell seed",
       [](Json& s) {
         s["objects"][0]["pointshell"] = {{"seed", 9}};
       },
       false, true, false},
      {"material", [](Json& s) { s["objects"][0]["model"]["material"]["young_modulus"] = 2e6; },
       false, false, true},
      {"anchors",
       [](Json& s) {
         s["objects"][0]["model"]["anchors"][0]["max"] = {1, 1, 0.2};
       },
       false, false, true},
      {"basis r",
       [](Json& s) {
         s["objects"][0]["model"]["basis"] = {{"r", 20}};
       },
       false, false, true},
      {"meshing",
       [](Json& s) {
         s["objects"][0]["model"]["meshing"] = {{"fill_interior", true}};
       },
       false, false, true},
  };
  const std::string field = base_key(Product::distance_field);
  const std::string shell = base_key(Product::pointshell);
  const std::string model = base_key(Product::reduced_model);
  for (const Edit& e : edits) {
    SCOPED_TRACE(e.what);
    EXPECT_EQ(key_after(e.edit, Product::distance_field) != field, e.field);
    EXPECT_EQ(key_after(e.edit, Product::pointshell) != shell, e.shell);
    EXPECT_EQ(key_after(e.edit, Product::reduced_model) != model, e.model);
  }
}

TEST(SceneContentKey, NonRepulsionPointshellsIgnoreTheField) {
  const auto vertices = [](Json& s) { s["objects"][0]["pointshell"] = {{"method", "vertices"}}; };
  const auto vertices_finer_field = [](Json& s) {
    s["objects"][0]["pointshell"] = {{"method", "vertices"}};
    s["objects"][0]["field"] = {{"cells", 256}};
  };
  EXPECT_EQ(key_after(vertices, Product::pointshell),
            key_after(vertices_finer_field, Product::pointshell));
  EXPECT_NE(key_after(vertices, Product::distance_field),
            key_after(vertices_finer_field, Product::distance_field));
}

TEST(SceneContentKey, MeshesEnterByContentNotByPath) {
  const std::filesystem::path copy = test::scratch_file("copy_of_cube.off");
  std::filesystem::copy_file(test::test_file("scenes/cube.off"), copy);
  const std::filesystem::path other = test::scratch_file("other.off");
  {
    std::ofstream out(other, std::ios::binary);
    out << test::read_bytes(test::test_file("scenes/cube.off")) << "# one more comment\n";
  }
  const std::string base = base_key(Product::distance_field);
  EXPECT_EQ(
      key_after([&](Json& s) { s["objects"][0]["mesh"] = copy.string(); }, Product::distance_field),
      base);
  EXPECT_NE(key_after([&](Json& s) { s["objects"][0]["mesh"] = other.string(); },
                      Product::distance_field),
            base);
}

TEST(SceneContentKey, LoadFilesEnterByContent) {
  const auto sketch = [](Json& s) {
    s["objects"][0]["model"]["basis"] = {{"method", "sketch"}, {"r", 2}, {"loads", "loads.csv"}};
  };
  const Json key = Json::parse(key_after(sketch, Product::reduced_model));
  EXPECT_EQ(key["model"]["basis"]["loads"], file_hash_hex(test::test_file("scenes/loads.csv")));
  EXPECT_EQ(key["model"]["basis"]["method"], "sketch");
}

TEST(SceneContentKey, ProductsAnObjectNeeds) {
  Json scene = base_scene();
  scene["objects"][0]["roles"] = {"pointshell"};
  scene["objects"][0]["pointshell"] = {{"method", "random"}, {"points", 100}};
  scene["objects"][1]["roles"] = {"distance_field"};
  const SceneDescription s = parse_scene(scene.dump(), "scene.json", test_options());
  const ObjectDescription& tool = s.objects[0];
  const ObjectDescription& wall = s.objects[1];
  EXPECT_FALSE(needs_product(tool, Product::distance_field));  // no repulsion: no field
  EXPECT_TRUE(needs_product(tool, Product::pointshell));
  EXPECT_TRUE(needs_product(tool, Product::reduced_model));
  EXPECT_TRUE(needs_product(wall, Product::distance_field));
  EXPECT_FALSE(needs_product(wall, Product::pointshell));
  EXPECT_FALSE(needs_product(wall, Product::reduced_model));
  EXPECT_TRUE(test::throws_with_message<reduced::Error>(
      [&] { content_key(wall, Product::reduced_model); },
      "content_key: object \"wall\" has no reduced_model"));
  EXPECT_TRUE(test::throws_with_message<reduced::Error>(
      [&] { content_key(tool, Product::distance_field); },
      "content_key: object \"tool\" has no distance_field"));
}

// The cache's file names: every existing cache entry is found again only if a key's text stays
// exactly this for key_version 1. Together the scenes below take every branch of a key (each
// pointshell method, both meshings, each basis method, soups and procedural meshes).
TEST(SceneContentKey, KeyTextsOfVersionOneStayTheSame) {
  const std::string cube = file_hash_hex(test::test_file("scenes/cube.off"));
  const std::string loads = file_hash_hex(test::test_file("scenes/loads.csv"));
  const auto key_of = [](const std::function<void(Json&)>& edit, Product product) {
    Json scene = base_scene();
    edit(scene);
    return content_key(tool_of(scene), product);
  };
  const auto nothing = [](Json&) {};
  struct Pinned {
    const char* what;
    std::function<void(Json&)> edit;
    Product product;
    std::string key;
  };
  const Pinned pinned[] = {
      {"base field", nothing, Product::distance_field,
       R"({"field":{"box_expansion":1.5,"cells":128,"exact_band":3.0,"soup":false},)"
       R"("geometry":{"centre":false,"scale":1.0},"key_version":1,"mesh":{"extension":".off",)"
       R"("xxh3":"<cube>"},"product":"distance_field"})"},
      {"base pointshell", nothing, Product::pointshell,
       R"({"geometry":{"centre":false,"scale":1.0},"key_version":1,"mesh":{"extension":".off",)"
       R"("xxh3":"<cube>"},"pointshell":{"field":{"box_expansion":1.5,"cells":128,)"
       R"("exact_band":3.0,"soup":false},"first_level_points":64,"levels":4,)"
       R"("max_iterations":1000,"method":"repulsion","radius_factor":1.5,"seed":0,)"
       R"("tolerance":0.001},"product":"pointshell"})"},
      {"base model", nothing, Product::reduced_model,
       R"({"geometry":{"centre":false,"scale":1.0},"key_version":1,"mesh":{"extension":".off",)"
       R"("xxh3":"<cube>"},"model":{"anchors":[{"max":[1.0,1.0,0.1],"min":[0.0,0.0,0.0],)"
       R"("type":"box"}],"basis":{"k":20,"mass":"consistent","max_restarts":300,)"
       R"("method":"modes","metric":"mass","modal_derivatives":true,"r":30,"tolerance":0.0},)"
       R"("material":{"density":1000.0,"poisson_ratio":0.45,"young_modulus":1000000.0},)"
       R"("meshing":{"enlargement":1.2,"fill_interior":false,"method":"voxels",)"
       R"("resolution":64}},"product":"reduced_model"})"},
      {"soup field",
       [](Json& s) {
         s["objects"][0]["field"] = {{"soup", true},
                                     {"offset", 0.02},
                                     {"cells", 32},
                                     {"box_expansion", 1.25},
                                     {"exact_band", 2}};
       },
       Product::distance_field,
       R"({"field":{"box_expansion":1.25,"cells":32,"exact_band":2.0,"offset":0.02,)"
       R"("soup":true},"geometry":{"centre":false,"scale":1.0},"key_version":1,)"
       R"("mesh":{"extension":".off","xxh3":"<cube>"},"product":"distance_field"})"},
      {"repulsion by points",
       [](Json& s) {
         s["objects"][0]["pointshell"] = {{"points", 1000},    {"levels", 3},
                                          {"seed", 2},         {"max_iterations", 10},
                                          {"tolerance", 0.01}, {"radius_factor", 2}};
       },
       Product::pointshell,
       R"({"geometry":{"centre":false,"scale":1.0},"key_version":1,"mesh":{"extension":".off",)"
       R"("xxh3":"<cube>"},"pointshell":{"field":{"box_expansion":1.5,"cells":128,)"
       R"("exact_band":3.0,"soup":false},"first_level_points":48,"levels":3,)"
       R"("max_iterations":10,"method":"repulsion","radius_factor":2.0,"seed":2,)"
       R"("tolerance":0.01},"product":"pointshell"})"},
      {"vertices",
       [](Json& s) {
         s["objects"][0]["pointshell"] = {{"method", "vertices"},
                                          {"first_level_points", 4},
                                          {"growth", 3},
                                          {"levels", 2},
                                          {"seed", 3}};
       },
       Product::pointshell,
       R"({"geometry":{"centre":false,"scale":1.0},"key_version":1,"mesh":{"extension":".off",)"
       R"("xxh3":"<cube>"},"pointshell":{"method":"vertices","schedule":{"first_level_size":4,)"
       R"("growth":3,"max_levels":2},"seed":3},"product":"pointshell"})"},
      {"random",
       [](Json& s) {
         s["objects"][0]["pointshell"] = {
             {"method", "random"}, {"points", 100}, {"seed", 18446744073709551615ull}};
       },
       Product::pointshell,
       R"({"geometry":{"centre":false,"scale":1.0},"key_version":1,"mesh":{"extension":".off",)"
       R"("xxh3":"<cube>"},"pointshell":{"method":"random","points":100,)"
       R"("schedule":{"first_level_size":8,"growth":8,"max_levels":0},)"
       R"("seed":18446744073709551615},"product":"pointshell"})"},
      {"voxels",
       [](Json& s) {
         s["objects"][0]["pointshell"] = {{"method", "voxels"}, {"cell_size", 0.1}};
       },
       Product::pointshell,
       R"({"geometry":{"centre":false,"scale":1.0},"key_version":1,"mesh":{"extension":".off",)"
       R"("xxh3":"<cube>"},"pointshell":{"cell_size":0.1,"method":"voxels",)"
       R"("schedule":{"first_level_size":8,"growth":8,"max_levels":0},"seed":0},)"
       R"("product":"pointshell"})"},
      {"tetrahedra and sketch",
       [](Json& s) {
         Json& model = s["objects"][0]["model"];
         model["meshing"] = {
             {"method", "tetrahedra"}, {"facet_size", 0.01}, {"seed", 7}, {"exude", false}};
         model["basis"] = Json::parse(R"({"method": "sketch", "r": 2, "loads": "loads.csv",
             "force_separation": 0.5, "deformation_kernel_width": 0.25, "rank_tolerance": 0.1,
             "static_solve": {"load_steps": 4, "line_search": false}})");
       },
       Product::reduced_model,
       R"({"geometry":{"centre":false,"scale":1.0},"key_version":1,"mesh":{"extension":".off",)"
       R"("xxh3":"<cube>"},"model":{"anchors":[{"max":[1.0,1.0,0.1],"min":[0.0,0.0,0.0],)"
       R"("type":"box"}],"basis":{"deformation_kernel_width":0.25,)"
       R"("deformation_separation":0.0,"force_kernel_width":0.0,"force_separation":0.5,)"
       R"("loads":"<loads>","method":"sketch","metric":"mass","r":2,"rank_tolerance":0.1,)"
       R"("skip_failed_solves":false,"static_solve":{"line_search":false,"load_steps":4,)"
       R"("max_iterations":50,"tolerance":1e-08}},"material":{"density":1000.0,)"
       R"("poisson_ratio":0.45,"young_modulus":1000000.0},)"
       R"("meshing":{"cell_radius_edge_ratio":2.0,"cell_size":0.0,"exude":false,)"
       R"("facet_angle":25.0,"facet_distance":0.0,"facet_size":0.01,"method":"tetrahedra",)"
       R"("perturb":false,"seed":7,"sliver_bound":10.0}},"product":"reduced_model"})"},
      {"simulation data",
       [](Json& s) {
         s["objects"][0]["model"]["basis"] = Json::parse(R"({"method": "simulation_data",
             "r": 3, "loads": "loads.csv", "metric": "euclidean",
             "simulation": {"hold_steps": 20, "snapshot_every": 5, "time_step": 0.002}})");
       },
       Product::reduced_model,
       R"({"geometry":{"centre":false,"scale":1.0},"key_version":1,"mesh":{"extension":".off",)"
       R"("xxh3":"<cube>"},"model":{"anchors":[{"max":[1.0,1.0,0.1],"min":[0.0,0.0,0.0],)"
       R"("type":"box"}],"basis":{"fixed_tolerance":1e-12,"loads":"<loads>",)"
       R"("method":"simulation_data","metric":"euclidean","r":3,"rank_tolerance":1e-10,)"
       R"("simulation":{"hold_steps":20,"mass_damping":0.0,"max_newton_iterations":10,)"
       R"("release_steps":0,"snapshot_every":5,"stiffness_damping":0.0,"time_step":0.002}},)"
       R"("material":{"density":1000.0,"poisson_ratio":0.45,"young_modulus":1000000.0},)"
       R"("meshing":{"enlargement":1.2,"fill_interior":false,"method":"voxels",)"
       R"("resolution":64}},"product":"reduced_model"})"},
      {"modes without derivatives",
       [](Json& s) {
         Json& model = s["objects"][0]["model"];
         model["meshing"] = {{"resolution", 10}, {"fill_interior", true}};
         model["basis"] = {{"k", 5}, {"modal_derivatives", false}, {"mass", "lumped"}};
       },
       Product::reduced_model,
       R"({"geometry":{"centre":false,"scale":1.0},"key_version":1,"mesh":{"extension":".off",)"
       R"("xxh3":"<cube>"},"model":{"anchors":[{"max":[1.0,1.0,0.1],"min":[0.0,0.0,0.0],)"
       R"("type":"box"}],"basis":{"k":5,"mass":"lumped","max_restarts":300,"method":"modes",)"
       R"("modal_derivatives":false,"r":5,"tolerance":0.0},"material":{"density":1000.0,)"
       R"("poisson_ratio":0.45,"young_modulus":1000000.0},"meshing":{"enlargement":1.2,)"
       R"("fill_interior":true,"method":"voxels","resolution":10}},"product":"reduced_model"})"},
      {"procedural shape",
       [](Json& s) {
         s["objects"][0]["mesh"] = "shape:peg";
         s["objects"][0]["size"] = 0.1;
         s["objects"][0]["centre"] = true;
       },
       Product::distance_field,
       R"({"field":{"box_expansion":1.5,"cells":128,"exact_band":3.0,"soup":false},)"
       R"("geometry":{"centre":true,"size":0.1},"key_version":1,"mesh":{"generator_version":1,)"
       R"("shape":"peg:side=0.02,length=0.08,chamfer=0.001"},"product":"distance_field"})"},
  };
  for (const Pinned& p : pinned) {
    SCOPED_TRACE(p.what);
    std::string expected = p.key;
    for (const auto& [name, hash] : {std::pair{"<cube>", cube}, std::pair{"<loads>", loads}}) {
      for (std::size_t at = expected.find(name); at != std::string::npos;
           at = expected.find(name)) {
        expected.replace(at, std::string_view(name).size(), hash);
      }
    }
    EXPECT_EQ(key_of(p.edit, p.product), expected);
  }
}

TEST(SceneContentKey, HashHex) {
  // XXH3-64 of the empty input (xxHash's reference value) and a known text.
  EXPECT_EQ(hash_hex(""), "2d06800538d394c2");
  const std::string hash = hash_hex(base_key(Product::pointshell));
  EXPECT_EQ(hash.size(), 16u);
  EXPECT_EQ(hash.find_first_not_of("0123456789abcdef"), std::string::npos);
  EXPECT_NE(hash, hash_hex(base_key(Product::distance_field)));
  EXPECT_TRUE(test::throws_with_message<reduced::IoError>(
      [] { file_hash_hex(std::filesystem::path(test::test_data_dir) / "scenes/absent.off"); },
      "absent.off"));
}

}  // namespace
}  // namespace khz::scene
