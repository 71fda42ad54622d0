// Scene preparation: each object gets exactly the products its roles and model need, through the
// product cache, so a second preparation computes nothing and reads the same bits, and a changed
// setting recomputes only the products whose keys it enters.
#include "scene_fixtures.hpp"

#include <khz/contact/field/deformed_distance_field.hpp>
#include <khz/contact/query/contact_query.hpp>
#include <khz/contact/query/contact_workspace.hpp>
#include <khz/reduced/io/mesh_file.hpp>
#include <khz/scene/body_mesh.hpp>
#include <khz/scene/cache_directory.hpp>
#include "scene_fixtures.hpp"

#include <khz/reduced/worker_threads.hpp>
#include <khz/scene/prepare_scene.hpp>
#include <khz/scene/read_scene.hpp>
#include <khz/test/fixtures.hpp>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <functional>
#include <optional>
#include <set>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

namespace khz::scene {
namespace {

using Json = nlohmann::json;
using Origin = PrepareRecord::Origin;

/// Reads a scene given as JSON; meshes resolve against tests/data/scenes (cube.off: the unit
/// cube [0, 1]³).
SceneDescription scene_of(const Json& scene, bool check_files = true) {
  SceneReadOptions options;
  options.base_directory = test::test_file("scenes");
  options.check_files = check_files;
  return parse_scene(scene.dump(), "scene.json", options);
}

/// A rigid 10 cm cube (distance field, 16 cells) and a rigid 5 cm cube held against it (300
/// random points in levels of 8, 32, …): neither needs the other's products.
Json rigid_scene() {
  return Json::parse(R"({
    "objects": [
      {"name": "wall", "mesh": "cube.off", "size": 0.1, "centre": true,
       "roles": ["distance_field"], "field": {"cells": 16}},
      {"name": "tool", "mesh": "cube.off", "size": 0.05, "centre": true, "roles": ["pointshell"],
       "pointshell": {"method": "random", "points": 300, "first_level_points": 8, "growth": 4}}
    ],
    "haptic": {"object": "tool"}
  })");
}

/// test_scenes::reduced_pair_scene(), its tool's integrator damped (α = 2/s).
Json reduced_scene() {
  Json scene = test_scenes::reduced_pair_scene();
  scene["objects"][0]["model"]["integrator"] = {{"mass_damping", 2.0}};
  return scene;
}

std::filesystem::path fresh_cache() { return test::scratch_directory("cache"); }

PreparedScene prepare(const Json& scene, const std::filesystem::path& cache_directory,
                      const PrepareOptions& options = {}) {
  ProductCache cache(cache_directory);
  return prepare_scene(scene_of(scene), cache, options);
}

/// (object, step, origin) of every record, for comparing what a preparation did.
using Done = std::tuple<std::string, PrepareStep, Origin>;
std::vector<Done> done(const PreparedScene& prepared) {
  std::vector<Done> result;
  for (const PrepareRecord& r : prepared.records) result.emplace_back(r.object, r.step, r.origin);
  return result;
}

/// The file names in the cache directory, sorted.
std::vector<std::string> cache_files(const std::filesystem::path& directory) {
  std::vector<std::string> names;
  for (const auto& entry : std::filesystem::directory_iterator(directory)) {
    names.push_back(entry.path().filename().string());
  }
  std::sort(names.begin(), names.end());
  return names;
}

/// The extensions of the cache's files, sorted (one per product file).
std::vector<std::string> cache_extensions(const std::filesystem::path& directory) {
  std::vector<std::string> extensions;
  for (const std::string& name : cache_files(directory)) {
    extensions.push_back(std::filesystem::path(name).extension().string());
  }
  std::sort(extensions.begin(), extensions.end());
  return extensions;
}

template <typename A, typename B>
bool same_bits(const A& a, const B& b) {
  return a.rows() == b.rows() && a.cols() == b.cols() && (a.array() == b.array()).all();
}

TEST(ScenePrepare, BodyFrameScalesBySizeOrScaleAndCentres) {
  const reduced::TriangleMesh cube = read_body_mesh(scene_of(rigid_scene()).objects[0]);
  EXPECT_TRUE(cube.vertices.colwise().minCoeff().isApprox(Eigen::RowVector3d::Constant(-0.05)));
  EXPECT_TRUE(cube.vertices.colwise().maxCoeff().isApprox(Eigen::RowVector3d::Constant(0.05)));

  ObjectDescription scaled = scene_of(rigid_scene()).objects[0];
  scaled.size.reset();
  scaled.scale = 2.0;
  scaled.centre = false;
  const reduced::TriangleMesh doubled = read_body_mesh(scaled);
  EXPECT_EQ(doubled.vertices.colwise().minCoeff(), Eigen::RowVector3d::Zero());
  EXPECT_EQ(doubled.vertices.colwise().maxCoeff(), Eigen::RowVector3d::Constant(2.0));
  EXPECT_EQ(doubled.triangles, cube.triangles);
}

/// Sets an environment variable for the scope, restoring the previous value (or its absence).
class ScopedVariable {
 public:
  ScopedVariable(const char* name, const char* value) : m_name(name) {
    if (const char* previous = std::getenv(name)) m_previous = previous;
    if (value != nullptr) {
      ::setenv(name, value, 1);
    } else {
      ::unsetenv(name);
    }
  }
  ~ScopedVariable() {
    if (m_previous) {
      ::setenv(m_name, m_previous->c_str(), 1);
    } else {
      ::unsetenv(m_name);
    }
  }
  ScopedVariable(const ScopedVariable&) = delete;
  ScopedVariable& operator=(const ScopedVariable&) = delete;

 private:
  const char* m_name;
  std::optional<std::string> m_previous;
};

TEST(ScenePrepare, TheDefaultCacheFollowsTheXdgRules) {
  {
    const ScopedVariable xdg("XDG_CACHE_HOME", "/var/cache/me");
    const ScopedVariable home("HOME", "/home/me");
    EXPECT_EQ(default_cache_directory(), "/var/cache/me/kilohertz");
  }
  {
    const ScopedVariable xdg("XDG_CACHE_HOME", "relative/ignored");
    const ScopedVariable home("HOME", "/home/me");
    EXPECT_EQ(default_cache_directory(), "/home/me/.cache/kilohertz");
  }
  {
    const ScopedVariable xdg("XDG_CACHE_HOME", nullptr);
    const ScopedVariable home("HOME", nullptr);
    EXPECT_TRUE(default_cache_directory().empty());
  }
}

TEST(ScenePrepare, RigidObjectsGetOnlyWhatTheirRolesNeed) {
  const std::filesystem::path directory = fresh_cache();
  const PreparedScene prepared = prepare(rigid_scene(), directory);

  // The field object has no pointshell, the pointshell object no field (random points need
  // none), and neither a model.
  const std::vector<Done> expected{{"wall", PrepareStep::distance_field, Origin::computed},
                                   {"tool", PrepareStep::pointshell, Origin::computed},
                                   {"tool", PrepareStep::point_tree, Origin::built}};
  EXPECT_EQ(done(prepared), expected);
  EXPECT_EQ(cache_extensions(directory), (std::vector<std::string>{".khzsdf", ".khzshell"}));

  ASSERT_EQ(prepared.objects.size(), 2U);
  const PreparedObject& wall = prepared.objects[0];
  const PreparedObject& tool = prepared.objects[1];
  ASSERT_NE(wall.field, nullptr);
  EXPECT_EQ(wall.field->geometry().cells, 16);
  EXPECT_LT(wall.field->distance(Eigen::Vector3d::Zero()), -0.04);  // the cube's centre
  EXPECT_EQ(wall.tree, nullptr);
  EXPECT_EQ(wall.model, nullptr);
  EXPECT_EQ(wall.deformed_field, nullptr);
  ASSERT_NE(tool.tree, nullptr);
  EXPECT_EQ(tool.tree->num_points(), 300);
  EXPECT_GT(tool.tree->num_levels(), 2);
  EXPECT_LE(tool.tree->pointshell().points.cwiseAbs().maxCoeff(), 0.025 + 1e-12);
  EXPECT_EQ(tool.field, nullptr);
  EXPECT_EQ(tool.model, nullptr);
  EXPECT_EQ(tool.embedding, nullptr);
  EXPECT_EQ(tool.deformable_tree, nullptr);
  EXPECT_EQ(prepared.description.objects.size(), 2U);
}

TEST(ScenePrepare, ASecondRigidPreparationReadsTheSameBits) {
  const std::filesystem::path directory = fresh_cache();
  const PreparedScene first = prepare(rigid_scene(), directory);
  ProductCache cache(directory);
  const PreparedScene second = prepare_scene(scene_of(rigid_scene()), cache);
  EXPECT_EQ(cache.computed_count(), 0);
  EXPECT_EQ(second.count(Origin::computed), 0);
  EXPECT_EQ(second.count(Origin::read), 2);

  const auto first_values = first.objects[0].field->values();
  const auto second_values = second.objects[0].field->values();
  EXPECT_TRUE(std::equal(first_values.begin(), first_values.end(), second_values.begin(),
                         second_values.end()));
  EXPECT_TRUE(same_bits(first.objects[1].tree->pointshell().points,
                        second.objects[1].tree->pointshell().points));
  EXPECT_TRUE(same_bits(first.objects[1].tree->pointshell().normals,
                        second.objects[1].tree->pointshell().normals));
}

TEST(ScenePrepare, ReducedObjectsGetAModelADeformableTreeAndADeformedField) {
  const std::filesystem::path directory = fresh_cache();
  PreparedScene prepared = prepare(reduced_scene(), directory);

  const std::vector<Done> expected{
      {"tool", PrepareStep::volume_mesh, Origin::computed},
      {"tool", PrepareStep::reduced_model, Origin::computed},
      {"tool", PrepareStep::distance_field, Origin::computed},  // the repulsion's level set
      {"tool", PrepareStep::pointshell, Origin::computed},
      {"tool", PrepareStep::point_tree, Origin::built},  // never stored
      {"wall", PrepareStep::volume_mesh, Origin::computed},
      {"wall", PrepareStep::reduced_model, Origin::computed},
      {"wall", PrepareStep::distance_field, Origin::computed},
      {"wall", PrepareStep::deformed_field, Origin::built}};
  EXPECT_EQ(done(prepared), expected);
  EXPECT_EQ(cache_extensions(directory),
            (std::vector<std::string>{".khzmodel", ".khzmodel", ".khzsdf", ".khzsdf", ".khzshell",
                                      ".msh", ".msh"}));
  for (const PrepareRecord& record : prepared.records) {
    EXPECT_EQ(record.file.empty(), record.origin == Origin::built);
    if (!record.file.empty()) {
      EXPECT_TRUE(std::filesystem::exists(record.file)) << record.file;
      EXPECT_EQ(record.file.filename().string().rfind(std::string(step_name(record.step)), 0), 0U)
          << record.file;
    }
  }

  const PreparedObject& tool = prepared.objects[0];
  const PreparedObject& wall = prepared.objects[1];
  ASSERT_NE(tool.model, nullptr);
  ASSERT_NE(tool.embedding, nullptr);
  ASSERT_NE(tool.deformable_tree, nullptr);
  EXPECT_EQ(tool.tree, nullptr);
  EXPECT_EQ(tool.field, nullptr);  // the repulsion's field is not kept: no distance_field role
  EXPECT_EQ(tool.model->dimension(), 4);
  EXPECT_EQ(tool.model->basis().vectors.rows(), 3 * tool.embedding->mesh().num_vertices());
  EXPECT_EQ(tool.embedding->mesh().num_elements(), 64);       // every voxel of the 4³ grid
  EXPECT_EQ(tool.model->basis().fixed_vertices.size(), 25U);  // the bottom layer, 5 × 5
  EXPECT_EQ(tool.model->defaults().newmark.mass_damping, 2.0);
  EXPECT_EQ(tool.deformable_tree->dimension(), 4);
  EXPECT_EQ(tool.deformable_tree->tree().num_points(), 16 + 64);
  ASSERT_NE(wall.model, nullptr);
  ASSERT_NE(wall.deformed_field, nullptr);
  EXPECT_EQ(wall.field, nullptr);  // the deformed field holds it
  EXPECT_EQ(wall.deformable_tree, nullptr);
  EXPECT_EQ(wall.model->dimension(), 3);
  EXPECT_EQ(wall.model->defaults().newmark.time_step, 1e-3);  // 1 / loop.rate_hz
  EXPECT_EQ(wall.deformed_field->num_proxies(), 12);
  EXPECT_EQ(wall.deformed_field->neighbours(), 4);

  // One contact query: the deformed tool, its centre 8 cm from the wall's, overlaps it by 1 cm.
  contact::DeformedFieldState field(*wall.deformed_field);
  ASSERT_TRUE(field.update(Eigen::VectorXd::Constant(3, 1e-3)));
  EXPECT_LT(field.distance(Eigen::Vector3d::Zero()), -0.04);
  contact::ContactOptions options;
  options.haptic_object = contact::HapticObject::pointshell;
  contact::ContactWorkspace workspace(*tool.deformable_tree, options, 3);
  contact::ContactFrames frames;
  frames.pointshell.translation() = Eigen::Vector3d(0.08, 0.0, 0.0);
  frames.grasp_point = Eigen::Vector3d(0.08, 0.0, 0.0);
  const Eigen::VectorXd q = Eigen::VectorXd::Constant(4, 1e-3);
  ASSERT_TRUE(contact::query_contact(*tool.deformable_tree, q, field, frames, workspace));
  const contact::ContactResult& result = workspace.result();
  EXPECT_TRUE(result.force.allFinite());
  EXPECT_GT(result.force.x(), 0.0);  // pushed back out, along +x
  ASSERT_EQ(result.pointshell_reduced_force.size(), 4);
  EXPECT_TRUE(result.pointshell_reduced_force.allFinite());
  ASSERT_EQ(result.field_reduced_force.size(), 3);
  EXPECT_TRUE(result.field_reduced_force.allFinite());

  // Moving the prepared scene leaves every product where it is: the state still refers to it.
  const contact::DeformedDistanceField* address = wall.deformed_field.get();
  const PreparedScene moved = std::move(prepared);
  EXPECT_EQ(moved.objects[1].deformed_field.get(), address);
  EXPECT_EQ(&field.field(), address);
}

TEST(ScenePrepare, ASecondReducedPreparationComputesNothingAndReadsTheSameBits) {
  const std::filesystem::path directory = fresh_cache();
  const PreparedScene first = prepare(reduced_scene(), directory);
  ProductCache cache(directory);
  const PreparedScene second = prepare_scene(scene_of(reduced_scene()), cache);
  EXPECT_EQ(cache.computed_count(), 0);
  // Everything is read, but the tool's field (its pointshell is not computed again); the tree
  // is built from the pointshell and the basis as the first time.
  const std::vector<Done> expected{{"tool", PrepareStep::volume_mesh, Origin::read},
                                   {"tool", PrepareStep::reduced_model, Origin::read},
                                   {"tool", PrepareStep::pointshell, Origin::read},
                                   {"tool", PrepareStep::point_tree, Origin::built},
                                   {"wall", PrepareStep::volume_mesh, Origin::read},
                                   {"wall", PrepareStep::reduced_model, Origin::read},
                                   {"wall", PrepareStep::distance_field, Origin::read},
                                   {"wall", PrepareStep::deformed_field, Origin::built}};
  EXPECT_EQ(done(second), expected);

  for (std::size_t i = 0; i < 2; ++i) {
    SCOPED_TRACE(first.description.objects[i].name);
    const PreparedObject& a = first.objects[i];
    const PreparedObject& b = second.objects[i];
    EXPECT_TRUE(same_bits(a.embedding->mesh().vertices, b.embedding->mesh().vertices));
    EXPECT_TRUE(same_bits(a.embedding->mesh().elements, b.embedding->mesh().elements));
    EXPECT_TRUE(same_bits(a.model->basis().vectors, b.model->basis().vectors));
    EXPECT_EQ(a.model->basis().fixed_vertices, b.model->basis().fixed_vertices);
    EXPECT_TRUE(same_bits(a.model->mass(), b.model->mass()));
    EXPECT_EQ(a.model->defaults().newmark.mass_damping, b.model->defaults().newmark.mass_damping);
  }
  const contact::DeformablePointTree& tree_a = *first.objects[0].deformable_tree;
  const contact::DeformablePointTree& tree_b = *second.objects[0].deformable_tree;
  EXPECT_TRUE(same_bits(tree_a.tree().pointshell().points, tree_b.tree().pointshell().points));
  for (Eigen::Index s = 0; s < tree_a.tree().num_points(); ++s) {
    ASSERT_TRUE(same_bits(tree_a.displacement_modes(s), tree_b.displacement_modes(s))) << s;
    ASSERT_TRUE(same_bits(tree_a.normal_modes(s), tree_b.normal_modes(s))) << s;
  }
  const contact::DeformedDistanceField& field_a = *first.objects[1].deformed_field;
  const contact::DeformedDistanceField& field_b = *second.objects[1].deformed_field;
  const auto values_a = field_a.field(0).values();
  const auto values_b = field_b.field(0).values();
  EXPECT_TRUE(std::equal(values_a.begin(), values_a.end(), values_b.begin(), values_b.end()));
  // The proxies are fitted again (not cached), from the same seed: the same field.
  EXPECT_TRUE(same_bits(field_a.rest_positions(), field_b.rest_positions()));
  EXPECT_TRUE(same_bits(field_a.displacement_matrix(), field_b.displacement_matrix()));
}

TEST(ScenePrepare, AChangedSettingRecomputesOnlyWhatDependsOnIt) {
  const std::filesystem::path directory = fresh_cache();
  prepare(reduced_scene(), directory);

  // A pointshell setting: the pointshell (from the cached field); the tree is built from it.
  Json reseeded = reduced_scene();
  reseeded["objects"][0]["pointshell"]["seed"] = 7;
  {
    ProductCache cache(directory);
    const PreparedScene prepared = prepare_scene(scene_of(reseeded), cache);
    const std::vector<Done> expected{{"tool", PrepareStep::volume_mesh, Origin::read},
                                     {"tool", PrepareStep::reduced_model, Origin::read},
                                     {"tool", PrepareStep::distance_field, Origin::read},
                                     {"tool", PrepareStep::pointshell, Origin::computed},
                                     {"tool", PrepareStep::point_tree, Origin::built},
                                     {"wall", PrepareStep::volume_mesh, Origin::read},
                                     {"wall", PrepareStep::reduced_model, Origin::read},
                                     {"wall", PrepareStep::distance_field, Origin::read},
                                     {"wall", PrepareStep::deformed_field, Origin::built}};
    EXPECT_EQ(done(prepared), expected);
    EXPECT_EQ(cache.computed_count(), 1);
  }

  // A material: the model (with its volume mesh, stored under the model's key); not the field
  // or the pointshell.
  Json stiffer = reduced_scene();
  stiffer["objects"][0]["model"]["material"]["young_modulus"] = 2e5;
  {
    ProductCache cache(directory);
    const PreparedScene prepared = prepare_scene(scene_of(stiffer), cache);
    const std::vector<Done> expected{{"tool", PrepareStep::volume_mesh, Origin::computed},
                                     {"tool", PrepareStep::reduced_model, Origin::computed},
                                     {"tool", PrepareStep::pointshell, Origin::read},
                                     {"tool", PrepareStep::point_tree, Origin::built}};
    const std::vector<Done> all = done(prepared);
    EXPECT_EQ(std::vector<Done>(all.begin(), all.begin() + 4), expected);
    EXPECT_EQ(cache.computed_count(), 2);
  }

  // The integrator, a name and a pose enter no key: nothing is computed, the defaults change.
  Json renamed = reduced_scene();
  renamed["objects"][0]["model"]["integrator"] = {{"mass_damping", 5.0}};
  renamed["objects"][1]["name"] = "floor";
  renamed["objects"][1]["pose"] = {{"position", {0.0, 0.0, -0.2}}};
  {
    ProductCache cache(directory);
    const PreparedScene prepared = prepare_scene(scene_of(renamed), cache);
    EXPECT_EQ(cache.computed_count(), 0);
    EXPECT_EQ(prepared.objects[0].model->defaults().newmark.mass_damping, 5.0);
    EXPECT_EQ(prepared.records.back().object, "floor");
  }
}

TEST(ScenePrepare, ObjectsWithEqualInputsShareOneProduct) {
  // The tool's repulsion field and the wall's field have the same inputs: one file, computed
  // for the first and read for the second.
  Json scene = rigid_scene();
  scene["objects"][1] = {{"name", "tool"},
                         {"mesh", "cube.off"},
                         {"size", 0.1},
                         {"centre", true},
                         {"roles", {"pointshell"}},
                         {"field", {{"cells", 16}}},
                         {"pointshell", {{"first_level_points", 8}, {"levels", 2}}}};
  const std::filesystem::path directory = fresh_cache();
  const PreparedScene prepared = prepare(scene, directory);
  const std::vector<Done> expected{{"wall", PrepareStep::distance_field, Origin::computed},
                                   {"tool", PrepareStep::distance_field, Origin::read},
                                   {"tool", PrepareStep::pointshell, Origin::computed},
                                   {"tool", PrepareStep::point_tree, Origin::built}};
  EXPECT_EQ(done(prepared), expected);
  EXPECT_EQ(prepared.records[0].file, prepared.records[1].file);
  EXPECT_EQ(cache_files(directory).size(), 2U);
}

TEST(ScenePrepare, EveryRecipeAndSamplingPrepares) {
  // A sketch basis and a voxel pointshell on the tool, a simulation-data basis and a soup field
  // on the wall, and a rigid post with a soup field and a repulsion pointshell on it.
  Json scene = reduced_scene();
  Json& tool = scene["objects"][0];
  tool["model"]["basis"] = {{"method", "sketch"}, {"r", 3}, {"loads", "voxel_cube_loads.csv"}};
  tool.erase("field");
  tool["pointshell"] = {{"method", "voxels"}, {"cell_size", 0.02}, {"first_level_points", 4}};
  Json& wall = scene["objects"][1];
  wall["model"]["basis"] = {{"method", "simulation_data"},
                            {"r", 3},
                            {"loads", "voxel_cube_loads.csv"},
                            {"simulation", {{"hold_steps", 1}, {"release_steps", 1}}}};
  wall["field"]["soup"] = true;
  scene["objects"].push_back(Json::parse(R"({
    "name": "post", "mesh": "cube.off", "size": 0.1, "centre": true,
    "roles": ["distance_field", "pointshell"],
    "field": {"cells": 16, "soup": true},
    "pointshell": {"method": "repulsion", "first_level_points": 8, "levels": 2}})"));

  const std::filesystem::path directory = fresh_cache();
  const PreparedScene prepared = prepare(scene, directory);
  const std::vector<Done> expected{{"tool", PrepareStep::volume_mesh, Origin::computed},
                                   {"tool", PrepareStep::reduced_model, Origin::computed},
                                   {"tool", PrepareStep::pointshell, Origin::computed},
                                   {"tool", PrepareStep::point_tree, Origin::built},
                                   {"wall", PrepareStep::volume_mesh, Origin::computed},
                                   {"wall", PrepareStep::reduced_model, Origin::computed},
                                   {"wall", PrepareStep::distance_field, Origin::computed},
                                   {"wall", PrepareStep::deformed_field, Origin::built},
                                   // the wall's soup field: the same inputs
                                   {"post", PrepareStep::distance_field, Origin::read},
                                   {"post", PrepareStep::pointshell, Origin::computed},
                                   {"post", PrepareStep::point_tree, Origin::built}};
  EXPECT_EQ(done(prepared), expected);

  const PreparedObject& sketched = prepared.objects[0];
  EXPECT_EQ(sketched.model->basis().recipe.rfind("sketch", 0), 0U)
      << sketched.model->basis().recipe;
  EXPECT_EQ(sketched.model->dimension(), 3);
  EXPECT_GT(sketched.deformable_tree->tree().num_points(), 4);
  const PreparedObject& simulated = prepared.objects[1];
  EXPECT_EQ(simulated.model->basis().recipe.rfind("simulation data: 8 snapshots", 0), 0U)
      << simulated.model->basis().recipe;
  const contact::DeformedFieldState field(*simulated.deformed_field);
  EXPECT_LT(field.distance(Eigen::Vector3d::Zero()), -0.04);
  const PreparedObject& post = prepared.objects[2];
  ASSERT_NE(post.field, nullptr);
  EXPECT_TRUE(post.field->is_signed());
  EXPECT_LT(post.field->distance(Eigen::Vector3d::Zero()), -0.04);
  ASSERT_NE(post.tree, nullptr);
  EXPECT_EQ(post.tree->num_points(), 8 + 32);
  // On the offset surface, σ = 1.4 spacings outside the cube's faces.
  const double sigma = 1.4 * post.field->geometry().spacing;
  EXPECT_GT(post.tree->pointshell().points.cwiseAbs().rowwise().maxCoeff().minCoeff(),
            0.05 + 0.5 * sigma);
}

TEST(ScenePrepare, ErrorsNameTheObjectAndStepAndNestTheCause) {
  const std::filesystem::path directory = fresh_cache();
  ProductCache cache(directory);

  Json missing = rigid_scene();
  missing["objects"][0]["mesh"] = "missing.off";
  try {
    prepare_scene(scene_of(missing, false), cache);
    ADD_FAILURE() << "a missing mesh was prepared";
  } catch (const PrepareError& error) {
    EXPECT_EQ(error.object(), "wall");
    EXPECT_EQ(error.step(), PrepareStep::distance_field);
    EXPECT_NE(std::string(error.what()).find("object \"wall\": distance_field: "),
              std::string::npos)
        << error.what();
    EXPECT_NE(error.cause().find("missing.off"), std::string::npos) << error.cause();
    EXPECT_THROW(std::rethrow_if_nested(error), reduced::IoError);
  }

  Json unanchored = reduced_scene();
  unanchored["objects"][1]["model"]["anchors"][0]["point"] = {0, 0, -1};
  EXPECT_TRUE(test::throws_with_message<PrepareError>(
      [&] { prepare_scene(scene_of(unanchored), cache); },
      "object \"wall\": reduced_model: the anchors select none of the volume mesh's 125 "
      "vertices"));
  Json anchored_everywhere = reduced_scene();
  anchored_everywhere["objects"][1]["model"]["anchors"][0]["point"] = {0, 0, 1};
  EXPECT_TRUE(test::throws_with_message<PrepareError>(
      [&] { prepare_scene(scene_of(anchored_everywhere), cache); },
      "object \"wall\": reduced_model: the anchors select all 125 of the volume mesh's vertices: "
      "nothing is left to deform"));
  // Nothing half-written stays behind.
  for (const std::string& name : cache_files(directory)) {
    EXPECT_EQ(name.find(".partial"), std::string::npos) << name;
  }
}

/// rigid_scene() with the wall made from `mesh` (a path), scaled to 10 cm and centred.
Json wall_of(const std::filesystem::path& mesh) {
  Json scene = rigid_scene();
  scene["objects"][0]["mesh"] = mesh.string();
  return scene;
}

TEST(ScenePrepare, AnOpenMeshGetsNoSignedFieldUnlessItsHolesAreFilledOrItIsASoup) {
  // CGAL's open_cube.off misses one face: without a defined inside its field would be signed by
  // guesswork, so it is refused in the scene's terms.
  Json open_box = wall_of(test::cgal_mesh("cube-ouvert.off"));
  EXPECT_TRUE(test::throws_with_message<PrepareError>(
      [&] { prepare(open_box, fresh_cache()); },
      "object \"wall\": distance_field: the mesh is not closed (4 boundary edges), so its inside "
      "is "
      "undefined and a signed distance field would be inside-out in places"));
  try {
    prepare(open_box, fresh_cache());
  } catch (const PrepareError& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("\"fill_holes\": true"), std::string::npos) << message;
    EXPECT_NE(message.find("\"soup\": true"), std::string::npos) << message;
  }

  // Filled, it is the cube [-1, 1]³: the centre a half side inside, the box boundary outside.
  // (The file also holds an unused vertex at (1, 2, 1), which "size" and "centre" count: the
  // longest side is 3, the body origin sits at file point (0, 0.5, 0).)
  open_box["objects"][0]["fill_holes"] = true;
  const PreparedScene filled = prepare(open_box, fresh_cache());
  const contact::DistanceGrid& field = *filled.objects[0].field;
  EXPECT_EQ(field.boundary_nodes_inside(), 0);
  const double scale = 0.1 / 3.0;
  EXPECT_NEAR(field.distance(Eigen::Vector3d(0.0, -0.5 * scale, 0.0)), -scale,
              0.5 * field.geometry().spacing);

  // As a soup it is signed by an offset surface instead.
  open_box["objects"][0].erase("fill_holes");
  open_box["objects"][0]["field"]["soup"] = true;
  EXPECT_EQ(prepare(open_box, fresh_cache()).objects[0].field->boundary_nodes_inside(), 0);
}

// A free body's mass properties are those of the solid its closed surface bounds: the 5 cm cube
// at a density, or at the density that gives a mass (the reference: a cube's m = ρ a³ and
// I = m a² / 6 about its centre). An open mesh has none, and is refused in the scene's terms.
TEST(ScenePrepare, AFreeBodyGetsTheMassPropertiesOfItsClosedSurface) {
  Json scene = rigid_scene();
  scene["objects"].push_back({{"name", "box"},
                              {"mesh", "cube.off"},
                              {"size", 0.05},
                              {"centre", true},
                              {"pose", {{"position", {0.0, 0.2, 0.0}}}},
                              {"roles", {"pointshell"}},
                              {"pointshell", {{"method", "vertices"}}},
                              {"dynamics", {{"density", 800.0}}}});
  const PreparedScene prepared = prepare(scene, fresh_cache());
  EXPECT_EQ(prepared.objects[1].mass_properties, nullptr) << "the held tool";
  ASSERT_NE(prepared.objects[2].mass_properties, nullptr);
  const reduced::MassProperties& box = *prepared.objects[2].mass_properties;
  const double side = 0.05, mass = 800.0 * side * side * side;
  EXPECT_NEAR(box.mass, mass, 1e-12 * mass);
  EXPECT_LE(box.centre.norm(), 1e-15);
  EXPECT_LE((box.inertia - Eigen::Matrix3d::Identity() * mass * side * side / 6.0).norm(),
            1e-12 * mass * side * side);
  EXPECT_EQ(prepared.records.back().object, "box");
  EXPECT_EQ(prepared.records.back().step, PrepareStep::mass_properties);
  EXPECT_EQ(prepared.records.back().origin, PrepareRecord::Origin::built);

  scene["objects"][2]["dynamics"] = {{"mass", 0.25}};
  const PreparedScene by_mass = prepare(scene, fresh_cache());
  EXPECT_NEAR(by_mass.objects[2].mass_properties->mass, 0.25, 1e-12);
  EXPECT_NEAR(by_mass.objects[2].mass_properties->inertia(0, 0), 0.25 * side * side / 6.0,
              1e-12 * side * side);

  scene["objects"][2]["mesh"] = test::cgal_mesh("cube-ouvert.off").string();
  EXPECT_TRUE(test::throws_with_message<PrepareError>(
      [&] { prepare(scene, fresh_cache()); },
      "object \"box\": mass_properties: the mesh is not closed (4 boundary edges), so its "
      "inside is undefined and it has no mass or inertia as a free body; give a closed mesh, or "
      "hold "
      "the object instead"));
}

TEST(ScenePrepare, AnOpenMeshIsNotTetrahedralized) {
  Json open_tool = reduced_scene();
  open_tool["objects"][0]["mesh"] = test::cgal_mesh("cube-ouvert.off").string();
  open_tool["objects"][0]["model"]["meshing"] = {{"method", "tetrahedra"}};
  open_tool["objects"][0]["roles"] = {"pointshell"};
  open_tool["objects"][0]["pointshell"] = {{"method", "vertices"}};
  open_tool["objects"][0].erase("field");
  EXPECT_TRUE(test::throws_with_message<PrepareError>(
      [&] { prepare(open_tool, fresh_cache()); },
      "object \"tool\": volume_mesh: the mesh is not closed (4 boundary edges), so its inside "
      "is undefined and it cannot be tetrahedralized; set \"fill_holes\": true on the object to "
      "close small holes, or mesh it with \"meshing\": {\"method\": \"voxels\"}"));
}

TEST(ScenePrepare, AClosedSelfIntersectingMeshIsPreparedWhenItsFieldIsNotInsideOut) {
  // CGAL's man.off: closed, 848 crossing triangle pairs (test_mesh_distance_field compares its
  // field with CGAL's ray parity).
  const PreparedScene prepared = prepare(wall_of(test::cgal_mesh("man.off")), fresh_cache());
  EXPECT_EQ(prepared.objects[0].field->boundary_nodes_inside(), 0);
}

TEST(ScenePrepare, AnInsideOutFieldIsRefused) {
  // dino.off with every triangle turned inward: closed, but its field puts the whole box inside.
  reduced::TriangleMesh dino = reduced::read_triangle_mesh(test::cgal_mesh("dino.off"));
  dino.triangles.col(1).swap(dino.triangles.col(2));
  const std::filesystem::path inverted = test::scratch_file("inverted_dino.off");
  reduced::write_triangle_mesh(inverted, dino);
  EXPECT_TRUE(test::throws_with_message<PrepareError>(
      [&] { prepare(wall_of(inverted), fresh_cache()); },
      "object \"wall\": distance_field: the signed distance field is inside-out: 1538 of the "
      "1538 nodes on the faces of its box"));
}

TEST(ScenePrepare, WarnsAboutSizesThatSuggestOtherUnitsThanMetres) {
  EXPECT_TRUE(prepare(rigid_scene(), fresh_cache()).warnings.empty());

  // A wall of 1000 m: an object in millimetres read as metres.
  Json huge = rigid_scene();
  huge["objects"][0].erase("size");
  huge["objects"][0]["scale"] = 1000.0;
  const PreparedScene kilometre = prepare(huge, fresh_cache());
  ASSERT_EQ(kilometre.warnings.size(), 1u);
  EXPECT_EQ(kilometre.warnings[0].object, "wall");
  EXPECT_NE(kilometre.warnings[0].message.find("it is 1000 m across, implausible"),
            std::string::npos)
      << kilometre.warnings[0].message;
  EXPECT_NE(kilometre.warnings[0].message.find("\"scale\""), std::string::npos);

  // Each size plausible alone, but a 6 m wall against a 5 cm tool: 120 times.
  Json mismatched = rigid_scene();
  mismatched["objects"][0]["size"] = 6.0;
  const PreparedScene apart = prepare(mismatched, fresh_cache());
  ASSERT_EQ(apart.warnings.size(), 1u);
  EXPECT_EQ(apart.warnings[0].object, "wall");
  EXPECT_NE(apart.warnings[0].message.find("times \"tool\""), std::string::npos)
      << apart.warnings[0].message;
}

TEST(ScenePrepare, WarnsAboutADeviceStartingTurnedAwayFromTheHeldObject) {
  // The tool lies turned a quarter turn about z; the (null) device reads the identity: the
  // coupling would turn the tool a quarter turn at the start.
  Json turned = rigid_scene();
  turned["objects"][1]["pose"] = Json::parse(R"({"rotation": {"axis": [0, 0, 1], "degrees": 90}})");
  const PreparedScene away = prepare(turned, fresh_cache());
  ASSERT_EQ(away.warnings.size(), 1u);
  EXPECT_EQ(away.warnings[0].object, "tool");
  EXPECT_NE(away.warnings[0].message.find("haptic entry 0's device starts turned 90 degrees"),
            std::string::npos)
      << away.warnings[0].message;
  EXPECT_NE(away.warnings[0].message.find("\"mapping\""), std::string::npos);

  // The device's frame turned with the tool, or the device itself turned: no warning; within
  // 10 degrees neither.
  Json mapped = turned;
  mapped["device"] =
      Json::parse(R"({"mapping": {"offset": {"rotation": {"axis": [0, 0, 1], "degrees": 90}}}})");
  EXPECT_TRUE(prepare(mapped, fresh_cache()).warnings.empty());
  Json held_turned = turned;
  held_turned["device"] =
      Json::parse(R"({"pose": {"rotation": {"axis": [0, 0, 1], "degrees": 85}}})");
  EXPECT_TRUE(prepare(held_turned, fresh_cache()).warnings.empty());
}

/// `file` rewritten with `edit` applied to its bytes.
template <typename Edit>
void damage(const std::filesystem::path& file, const Edit& edit) {
  std::string bytes = test::read_bytes(file);
  edit(bytes);
  std::ofstream(file, std::ios::binary | std::ios::trunc) << bytes;
}

/// The volume mesh text with one digit of the second node's first coordinate changed: it still
/// reads, as another mesh.
void change_a_coordinate(std::string& text) {
  const std::size_t node = text.find("\n2 ", text.find("$Nodes"));
  ASSERT_NE(node, std::string::npos);
  const std::size_t end = text.find(' ', node + 3);
  char& digit = text[end - 1];
  ASSERT_TRUE(std::isdigit(static_cast<unsigned char>(digit))) << text.substr(node, 40);
  digit = digit == '9' ? '1' : static_cast<char>(digit + 1);
}

TEST(ScenePrepare, ADamagedCacheFileIsComputedAgainWithAWarningNeverTrusted) {
  const std::filesystem::path original = fresh_cache();
  const PreparedScene first = prepare(reduced_scene(), original);
  struct Case {
    std::string extension, object;
    PrepareStep step;
    std::function<void(std::string&)> edit;
  };
  const auto flip = [](std::string& bytes) { bytes[bytes.size() / 2] ^= 0x10; };
  const auto cut = [](std::string& bytes) { bytes.resize(bytes.size() / 2); };
  const std::vector<Case> cases{
      {".khzmodel", "tool", PrepareStep::reduced_model, flip},
      {".khzmodel", "tool", PrepareStep::reduced_model, cut},
      {".khzshell", "tool", PrepareStep::pointshell, flip},
      {".khzsdf", "wall", PrepareStep::distance_field, cut},
      {".msh", "tool", PrepareStep::volume_mesh, change_a_coordinate},
      {".msh", "wall", PrepareStep::volume_mesh, cut},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.object + " " + c.extension);
    const std::filesystem::path directory = test::scratch_directory("damaged");  // removed
    std::filesystem::copy(original, directory);
    std::optional<std::filesystem::path> damaged;
    for (const PrepareRecord& record : first.records) {
      if (record.object == c.object && record.step == c.step) damaged = record.file;
    }
    ASSERT_TRUE(damaged && damaged->extension() == c.extension);
    damage(directory / damaged->filename(), c.edit);

    const PreparedScene second = prepare(reduced_scene(), directory);
    std::vector<Done> recomputed;
    for (const Done& d : done(second)) {
      if (std::get<2>(d) == Origin::computed) recomputed.push_back(d);
    }
    EXPECT_EQ(recomputed, (std::vector<Done>{{c.object, c.step, Origin::computed}}));
    ASSERT_EQ(second.warnings.size(), 1u);
    EXPECT_EQ(second.warnings[0].object, c.object);
    EXPECT_NE(second.warnings[0].message.find("the cached " + std::string(step_name(c.step)) +
                                              " could not be used and was computed again ("),
              std::string::npos)
        << second.warnings[0].message;
    // What was computed again is what the first preparation computed, and it replaced the
    // damaged file: a third preparation reads everything.
    for (std::size_t i = 0; i < 2; ++i) {
      EXPECT_TRUE(same_bits(first.objects[i].model->mass(), second.objects[i].model->mass()));
      EXPECT_TRUE(same_bits(first.objects[i].embedding->mesh().vertices,
                            second.objects[i].embedding->mesh().vertices));
    }
    EXPECT_TRUE(same_bits(first.objects[0].deformable_tree->displacement_modes(7),
                          second.objects[0].deformable_tree->displacement_modes(7)));
    const auto values_a = first.objects[1].deformed_field->field(0).values();
    const auto values_b = second.objects[1].deformed_field->field(0).values();
    EXPECT_TRUE(std::equal(values_a.begin(), values_a.end(), values_b.begin(), values_b.end()));
    ProductCache cache(directory);
    prepare_scene(scene_of(reduced_scene()), cache);
    EXPECT_EQ(cache.computed_count(), 0);
  }
}

// A scene's "threads" bounds its preparation's threads (reduced::worker_threads(), which the
// precomputations read: test_reduced_worker_threads counts what runs) and only its preparation.
TEST(ScenePrepare, TheScenesThreadsHoldDuringItsPreparation) {
  reduced::set_worker_threads(0);
  const int before = reduced::worker_threads();
  Json scene = rigid_scene();
  scene["threads"] = 1;
  std::set<int> seen;
  PrepareOptions options;
  options.progress = [&](const std::string&, PrepareStep, const reduced::Progress&) {
    seen.insert(reduced::worker_threads());
    return true;
  };
  prepare(scene, fresh_cache(), options);
  EXPECT_EQ(seen, std::set<int>{1});
  EXPECT_EQ(reduced::worker_threads(), before);
  seen.clear();
  prepare(rigid_scene(), fresh_cache(), options);
  EXPECT_EQ(seen, std::set<int>{before});
}

TEST(ScenePrepare, ProgressNamesObjectAndStepAndCanCancel) {
  const std::filesystem::path directory = fresh_cache();
  std::set<std::pair<std::string, PrepareStep>> reported;
  std::set<std::string> stages;
  PrepareOptions options;
  options.progress = [&](const std::string& object, PrepareStep step,
                         const reduced::Progress& progress) {
    EXPECT_LE(progress.done, progress.total);
    reported.emplace(object, step);
    stages.emplace(progress.stage);
    return true;
  };
  prepare(reduced_scene(), directory, options);
  for (const auto& [object, step] : {std::pair{"tool", PrepareStep::volume_mesh},
                                     {"tool", PrepareStep::reduced_model},
                                     {"tool", PrepareStep::distance_field},
                                     {"tool", PrepareStep::pointshell},
                                     {"tool", PrepareStep::point_tree},
                                     {"wall", PrepareStep::deformed_field}}) {
    EXPECT_TRUE(reported.count({object, step})) << object << " " << step_name(step);
  }
  for (const char* stage :
       {"voxelization", "linear modes", "modal derivatives", "reduced polynomials",
        "distance field", "particle repulsion level 1", "proxy modes"}) {
    EXPECT_TRUE(stages.count(stage)) << stage;
  }

  // Cancelling in the middle of the first product leaves no file, partial or complete.
  const std::filesystem::path cancelled = test::scratch_directory("cancelled");
  options.progress = [](const std::string&, PrepareStep, const reduced::Progress& progress) {
    return progress.stage != "distance field" || progress.done == 0;
  };
  EXPECT_THROW(prepare(rigid_scene(), cancelled, options), reduced::Cancelled);
  EXPECT_TRUE(cache_files(cancelled).empty());
}

}  // namespace
}  // namespace khz::scene
