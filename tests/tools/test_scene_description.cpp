// Scene files that are valid: what they read as, and that everything a scene leaves out takes
// the default of the library option it maps to.
#include <khz/contact/field/deformed_distance_field.hpp>
#include <khz/contact/field/mesh_distance_field.hpp>
#include <khz/contact/field/polygon_soup_field.hpp>
#include <khz/contact/pointshell/repulsion_pointshell.hpp>
#include <khz/haptic/device/null_device.hpp>
#include <khz/reduced/basis/modal_derivative_basis.hpp>
#include <khz/reduced/basis/simulation_data_basis.hpp>
#include <khz/reduced/basis/sketch_basis.hpp>
#include <khz/reduced/solvers/full_newmark.hpp>
#include <khz/scene/read_scene.hpp>
#include <khz/scene/scene_error.hpp>
#include <khz/test/data_paths.hpp>
#include <khz/test/fixtures.hpp>

#include "scene_fixtures.hpp"

#include <gtest/gtest.h>
#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <numbers>
#include <string>

namespace khz::scene {
namespace {

using Json = nlohmann::json;

/// Relative paths in the scenes below resolve against tests/data/scenes (cube.off, loads.csv,
/// press.csv).
SceneReadOptions test_options() { return test_scenes::read_options(); }

SceneDescription parse(const Json& scene) {
  return parse_scene(scene.dump(2), "scene.json", test_options());
}

using test_scenes::minimal_scene;

/// minimal_scene() with the tool a reduced model (material given, all else default).
Json reduced_scene() {
  Json scene = minimal_scene();
  scene["objects"][0]["model"] = {
      {"type", "reduced"},
      {"material", {{"young_modulus", 1e6}, {"poisson_ratio", 0.45}, {"density", 1000}}}};
  return scene;
}

TEST(SceneDescription, MinimalSceneResolvesNamesRolesAndPaths) {
  const SceneDescription scene = parse(minimal_scene());
  EXPECT_EQ(scene.source, "scene.json");
  EXPECT_EQ(scene.version, 2);
  ASSERT_EQ(scene.objects.size(), 2u);
  const ObjectDescription& tool = scene.objects[0];
  EXPECT_EQ(tool.name, "tool");
  EXPECT_EQ(tool.mesh, "cube.off");
  EXPECT_EQ(tool.mesh_path, (test::test_file("scenes") / "cube.off").lexically_normal());
  EXPECT_TRUE(tool.mesh_path.is_absolute());
  EXPECT_TRUE(tool.roles.pointshell);
  EXPECT_FALSE(tool.roles.distance_field);
  EXPECT_FALSE(scene.objects[1].roles.pointshell);
  EXPECT_TRUE(scene.objects[1].roles.distance_field);
  EXPECT_EQ(scene.haptic.front().object, "tool");
  EXPECT_EQ(scene.haptic.front().object_index, 0);
  EXPECT_EQ(&scene.held_object(), &scene.objects[0]);
  EXPECT_EQ(scene.haptic.front().role, contact::HapticObject::pointshell);
  EXPECT_EQ(scene.contact.haptic_object, contact::HapticObject::pointshell);
  EXPECT_TRUE(scene.haptic.front().grasp_at_centre);
}

// Version 2: "haptic" as a list, each hand with its object, role, grasp point and device; a
// version-1 file (one hand, top-level device) reads into the same structure.
TEST(SceneDescription, SeveralHandsEachWithItsDevice) {
  Json scene = minimal_scene();
  scene["version"] = 2;
  scene["objects"][1]["roles"] = {"distance_field", "pointshell"};
  scene["haptic"] = Json::parse(R"([
    {"object": "tool", "device": {"type": "null", "pose": {"position": [0, 0.1, 0]}}},
    {"object": "wall", "role": "distance_field", "grasp_point": [0, 0, 0.01],
     "device": {"type": "operator", "keyframes": [{"time": 1, "position": [0, 0, 0]}]}}
  ])");
  const SceneDescription s = parse(scene);
  ASSERT_EQ(s.haptic.size(), 2u);
  EXPECT_EQ(s.haptic[0].object_index, 0);
  EXPECT_EQ(s.haptic[0].role, contact::HapticObject::pointshell);
  EXPECT_EQ(s.haptic[0].device.type, DeviceType::null);
  EXPECT_EQ(s.haptic[0].device.null_pose.position.y(), 0.1);
  EXPECT_EQ(&s.held_object(1), &s.objects[1]);
  EXPECT_EQ(s.haptic[1].role, contact::HapticObject::distance_field);
  EXPECT_FALSE(s.haptic[1].grasp_at_centre);
  EXPECT_EQ(s.haptic[1].device.type, DeviceType::simulated_operator);
  EXPECT_EQ(s.contact.haptic_object, contact::HapticObject::pointshell);  // the first hand's

  Json version_1 = minimal_scene();
  version_1["version"] = 1;
  version_1["device"] = {{"type", "null"}, {"pose", {{"position", {0, 0.2, 0}}}}};
  const SceneDescription one = parse(version_1);
  EXPECT_EQ(one.version, 1);
  ASSERT_EQ(one.haptic.size(), 1u);
  EXPECT_EQ(one.haptic[0].device.null_pose.position.y(), 0.2);
}

TEST(SceneDescription, ObjectDefaultsAreTheLibraryDefaults) {
  const SceneDescription scene = parse(minimal_scene());
  const ObjectDescription& tool = scene.objects[0];
  EXPECT_EQ(tool.scale, 1.0);
  EXPECT_FALSE(tool.size.has_value());
  EXPECT_FALSE(tool.centre);
  EXPECT_TRUE(tool.pose.position.isZero());
  EXPECT_TRUE(tool.pose.orientation.coeffs().isApprox(Eigen::Quaterniond::Identity().coeffs()));
  EXPECT_EQ(tool.model.type, ModelType::rigid);
  EXPECT_FALSE(tool.is_reduced());

  const contact::DistanceFieldOptions field_options;
  const contact::PolygonSoupFieldOptions soup_options;
  const contact::DeformedFieldOptions deformed_options;
  const FieldDescription& field = scene.objects[1].field;
  EXPECT_EQ(field.distance.cells, field_options.cells);
  EXPECT_EQ(field.distance.box_expansion, field_options.box_expansion);
  EXPECT_EQ(field.distance.exact_band, field_options.exact_band);
  EXPECT_FALSE(field.soup);
  EXPECT_EQ(field.offset, soup_options.offset);
  EXPECT_EQ(field.deformed.proxies, deformed_options.proxies);
  EXPECT_EQ(field.deformed.neighbours, deformed_options.neighbours);
  EXPECT_EQ(field.deformed.seed, deformed_options.seed);

  const contact::RepulsionOptions repulsion;
  const PointshellDescription& shell = tool.pointshell;
  EXPECT_EQ(shell.method, PointshellMethod::repulsion);
  EXPECT_EQ(shell.repulsion.first_level_points, repulsion.first_level_points);
  EXPECT_EQ(shell.repulsion.levels, repulsion.levels);
  EXPECT_EQ(shell.repulsion.seed, repulsion.seed);
  EXPECT_EQ(shell.repulsion.max_iterations, repulsion.max_iterations);
  EXPECT_EQ(shell.repulsion.tolerance, repulsion.tolerance);
  EXPECT_EQ(shell.repulsion.radius_factor, repulsion.radius_factor);
  const contact::NestedLevelOptions nested;
  EXPECT_EQ(shell.nested.seed, nested.seed);
  EXPECT_EQ(shell.nested.schedule.first_level_size, nested.schedule.first_level_size);
  EXPECT_EQ(shell.nested.schedule.growth, nested.schedule.growth);
  EXPECT_EQ(shell.nested.schedule.max_levels, nested.schedule.max_levels);
  EXPECT_TRUE(tool.uses_field());  // repulsion samples the level set of its own field
  EXPECT_TRUE(scene.objects[1].uses_field());
}

TEST(SceneDescription, ReducedModelDefaultsAreTheLibraryDefaults) {
  const SceneDescription scene = parse(reduced_scene());
  const ModelDescription& model = scene.objects[0].model;
  ASSERT_EQ(model.type, ModelType::reduced);
  EXPECT_EQ(model.material.young_modulus, 1e6);
  EXPECT_EQ(model.material.poisson_ratio, 0.45);
  EXPECT_EQ(model.material.density, 1000.0);
  EXPECT_TRUE(model.anchors.empty());

  const reduced::VoxelizeOptions voxels;
  const reduced::TetrahedralizeOptions tets;
  EXPECT_EQ(model.meshing.method, MeshingMethod::voxels);
  EXPECT_EQ(model.meshing.voxels.resolution, voxels.resolution);
  EXPECT_EQ(model.meshing.voxels.enlargement, voxels.enlargement);
  EXPECT_EQ(model.meshing.voxels.fill_interior, voxels.fill_interior);
  EXPECT_EQ(model.meshing.tetrahedra.facet_angle, tets.facet_angle);
  EXPECT_EQ(model.meshing.tetrahedra.seed, tets.seed);

  const reduced::ModalDerivativeBasisOptions derivative_basis;
  const BasisDescription& basis = model.basis;
  EXPECT_EQ(basis.method, BasisMethod::modes);
  EXPECT_TRUE(basis.modal_derivatives);
  EXPECT_EQ(basis.basis_size(), derivative_basis.basis_size);
  EXPECT_EQ(basis.modal.modes.num_modes, derivative_basis.modes.num_modes);
  EXPECT_EQ(basis.modal.modes.mass, derivative_basis.modes.mass);
  EXPECT_EQ(basis.modal.modes.tolerance, derivative_basis.modes.tolerance);
  EXPECT_EQ(basis.modal.modes.max_restarts, derivative_basis.modes.max_restarts);
  EXPECT_EQ(basis.modal.metric, derivative_basis.metric);

  const reduced::SketchBasisOptions sketch;
  EXPECT_EQ(basis.sketch.force_separation, sketch.force_separation);
  EXPECT_EQ(basis.sketch.force_kernel_width, sketch.force_kernel_width);
  EXPECT_EQ(basis.sketch.deformation_separation, sketch.deformation_separation);
  EXPECT_EQ(basis.sketch.deformation_kernel_width, sketch.deformation_kernel_width);
  EXPECT_EQ(basis.sketch.rank_tolerance, sketch.rank_tolerance);
  EXPECT_EQ(basis.sketch.skip_failed_solves, sketch.skip_failed_solves);
  EXPECT_EQ(basis.sketch.static_solve.load_steps, sketch.static_solve.load_steps);
  EXPECT_EQ(basis.sketch.static_solve.max_iterations, sketch.static_solve.max_iterations);
  EXPECT_EQ(basis.sketch.static_solve.tolerance, sketch.static_solve.tolerance);
  EXPECT_EQ(basis.sketch.static_solve.line_search, sketch.static_solve.line_search);
  const reduced::SimulationDataBasisOptions simulation;
  EXPECT_EQ(basis.simulation_data.rank_tolerance, simulation.rank_tolerance);
  EXPECT_EQ(basis.simulation_data.fixed_tolerance, simulation.fixed_tolerance);
  const reduced::FullNewmarkOptions full;
  EXPECT_EQ(basis.simulation.integrator.newmark.time_step, full.newmark.time_step);
  EXPECT_EQ(basis.simulation.integrator.max_newton_iterations, full.max_newton_iterations);

  // The integrator: the library's defaults, but the time step is the loop's period.
  const reduced::ReducedNewmarkOptions newmark;
  EXPECT_EQ(model.integrator.newmark.time_step, 1.0 / scene.loop.rate_hz);
  EXPECT_EQ(model.integrator.newmark.beta, newmark.newmark.beta);
  EXPECT_EQ(model.integrator.newmark.gamma, newmark.newmark.gamma);
  EXPECT_EQ(model.integrator.newmark.mass_damping, newmark.newmark.mass_damping);
  EXPECT_EQ(model.integrator.newmark.stiffness_damping, newmark.newmark.stiffness_damping);
  EXPECT_EQ(model.integrator.max_newton_iterations, newmark.max_newton_iterations);
  EXPECT_EQ(model.integrator.tolerance, newmark.tolerance);
  EXPECT_EQ(model.integrator.acceleration_limit, std::numeric_limits<double>::infinity());
}

TEST(SceneDescription, SceneDefaultsAreTheLibraryDefaults) {
  const SceneDescription scene = parse(minimal_scene());
  const contact::ContactOptions contact;
  EXPECT_EQ(scene.contact.stiffness, contact.stiffness);
  EXPECT_EQ(scene.contact.scaling_count, contact.scaling_count);
  EXPECT_EQ(scene.contact.max_level, contact.max_level);
  EXPECT_EQ(scene.contact.gradient, contact.gradient);
  EXPECT_EQ(scene.contact.degradation.mode, contact.degradation.mode);
  EXPECT_EQ(scene.contact.degradation.budget_microseconds, contact.degradation.budget_microseconds);
  EXPECT_EQ(scene.contact.coherence.enabled, contact.coherence.enabled);
  EXPECT_EQ(scene.contact.coherence.max_skip, contact.coherence.max_skip);

  const haptic::CouplingOptions coupling;
  EXPECT_EQ(scene.coupling.stiffness, coupling.stiffness);
  EXPECT_EQ(scene.coupling.torque_stiffness, coupling.torque_stiffness);
  EXPECT_EQ(scene.coupling.static_damping, coupling.static_damping);
  EXPECT_EQ(scene.coupling.max_speed, coupling.max_speed);
  EXPECT_EQ(scene.coupling.max_angular_speed, coupling.max_angular_speed);
  EXPECT_EQ(scene.coupling.saturation_force, coupling.saturation_force);
  EXPECT_EQ(scene.coupling.object_radius, coupling.object_radius);
  EXPECT_EQ(scene.coupling.device_max_stiffness, coupling.device_max_stiffness);
  EXPECT_EQ(scene.coupling.degenerate_threshold, coupling.degenerate_threshold);
  EXPECT_EQ(scene.coupling.rotation_length, coupling.rotation_length);
  EXPECT_EQ(scene.coupling.period, 1.0 / scene.loop.rate_hz);

  const haptic::LoopOptions loop;
  EXPECT_EQ(scene.loop.rate_hz, loop.rate_hz);
  EXPECT_EQ(scene.loop.realtime_priority, loop.realtime_priority);
  EXPECT_EQ(scene.loop.priority, loop.priority);
  EXPECT_EQ(scene.loop.cpu, loop.cpu);
  EXPECT_EQ(scene.duration, 0.0);

  const DeviceDescription& device = scene.haptic.front().device;
  EXPECT_EQ(device.type, DeviceType::null);
  const haptic::DeviceCapabilities null_capabilities = haptic::NullDevice::default_capabilities();
  EXPECT_EQ(device.capabilities.name, null_capabilities.name);
  EXPECT_EQ(device.capabilities.max_force, null_capabilities.max_force);
  EXPECT_EQ(device.capabilities.nominal_rate, scene.loop.rate_hz);
  const haptic::WorkspaceMapping mapping;
  EXPECT_EQ(device.mapping.scale, mapping.scale);
  EXPECT_EQ(device.mapping.force_scale, mapping.force_scale);
  const haptic::SafetyOptions safety;
  EXPECT_EQ(device.safety.max_force, safety.max_force);
  EXPECT_EQ(device.safety.ramp_cycles, safety.ramp_cycles);
  EXPECT_EQ(device.safety.index_button, safety.index_button);
}

TEST(SceneDescription, EverySettingReachesItsMember) {
  Json scene = Json::parse(R"({
    "version": 1,
    "description": "every setting",
    "objects": [
      {
        "name": "tool", "mesh": "cube.off", "size": 0.05, "centre": true,
        "pose": {"position": [0.1, 0.2, 0.3], "rotation": {"axis": [0, 0, 2], "degrees": 90}},
        "roles": ["pointshell", "distance_field"],
        "model": {
          "type": "reduced",
          "meshing": {"method": "tetrahedra", "facet_size": 0.01, "facet_angle": 20,
                      "seed": 7, "exude": false},
          "material": {"young_modulus": 2e6, "poisson_ratio": 0.3, "density": 900},
          "anchors": [
            {"type": "box", "min": [0, 0, 0], "max": [0.01, 0.02, 0.03]},
            {"type": "half_space", "point": [0, 0, 0.04], "normal": [0, 0, 3]}
          ],
          "basis": {"method": "modes", "k": 4, "r": 10, "mass": "lumped",
                    "metric": "euclidean", "tolerance": 1e-9, "max_restarts": 10},
          "integrator": {"time_step": 0.002, "mass_damping": 0.5, "stiffness_damping": 0.01,
                         "max_newton_iterations": 3, "acceleration_limit": 1e4}
        },
        "field": {"cells": 64, "box_expansion": 2, "exact_band": 4, "proxies": 30,
                  "neighbours": 6, "seed": 18446744073709551615},
        "pointshell": {"method": "vertices", "first_level_points": 4, "growth": 3, "levels": 2,
                       "seed": 3}
      },
      {"name": "wall", "mesh": "cube.off", "scale": 2, "roles": ["pointshell"]}
    ],
    "haptic": {"object": "tool", "role": "distance_field", "grasp_point": [0.01, 0.02, 0.03]},
    "contact": {
      "stiffness": 2000, "scaling_count": 5, "max_level": 3, "gradient": "normal_direction",
      "onset_voxels": 0.3, "onset_depth": 1e-4,
      "degradation": {"mode": "time_budget", "budget_microseconds": 100, "cold_fraction": 0.5,
                      "contact_weight": 1.5},
      "coherence": {"enabled": true, "max_translation": 0.001, "max_rotation": 0.01,
                    "max_deformation": 0.002, "max_field_deformation": 0.003, "max_skip": 64},
      "friction": {"static": 0.4, "kinetic": 0.3, "stick_distance": 2e-4},
      "pairs": [{"objects": ["wall", "tool"], "friction": {"static": 0.7}}]
    },
    "coupling": {"stiffness": 400, "torque_stiffness": 2, "static_damping": 0.25,
                 "max_speed": 1, "max_angular_speed": 3, "saturation_force": 4,
                 "object_radius": 0.05, "max_rendered_force": 8, "max_rendered_torque": 0.4,
                 "device_max_stiffness": 3000, "degenerate_threshold": 0.01,
                 "rotation_length": 0.1},
    "device": {
      "type": "operator",
      "keyframes": [{"time": 0, "position": [0, 0, 0]},
                    {"time": 1, "position": [0, 0, -0.01],
                     "rotation": {"axis": [1, 0, 0], "degrees": 10}}],
      "hand": {"stiffness": 200, "damping": 5},
      "dynamics": {"mass": 0.2},
      "substeps": 4, "start_at_target": false,
      "initial_pose": {"position": [0, 0, 0.01]},
      "capabilities": {"max_force": 5, "output_dof": 3},
      "mapping": {"scale": 2, "offset": {"position": [0, 0, 0.5]}, "force_scale": 0.5},
      "safety": {"max_force": 4, "ramp_cycles": 10, "index_button": 0,
                 "index_orientation": false, "passivity_control": true,
                 "passivity_max_damping": 3, "passivity_max_rotational_damping": 0.01}
    },
    "loop": {"rate_hz": 500, "duration": 2.5, "realtime_priority": true, "priority": 90,
             "cpu": 1}
  })");
  const SceneDescription s = parse(scene);
  EXPECT_EQ(s.description, "every setting");
  const ObjectDescription& tool = s.objects[0];
  ASSERT_TRUE(tool.size.has_value());
  EXPECT_EQ(*tool.size, 0.05);
  EXPECT_TRUE(tool.centre);
  EXPECT_TRUE(tool.pose.position.isApprox(Eigen::Vector3d(0.1, 0.2, 0.3)));
  const Eigen::Quaterniond quarter_turn(
      Eigen::AngleAxisd(std::numbers::pi / 2, Eigen::Vector3d::UnitZ()));
  EXPECT_TRUE(tool.pose.orientation.isApprox(quarter_turn)) << tool.pose.orientation.coeffs();
  EXPECT_TRUE(tool.roles.pointshell && tool.roles.distance_field);

  const ModelDescription& model = tool.model;
  EXPECT_EQ(model.meshing.method, MeshingMethod::tetrahedra);
  EXPECT_EQ(model.meshing.tetrahedra.facet_size, 0.01);
  EXPECT_EQ(model.meshing.tetrahedra.facet_angle, 20.0);
  EXPECT_EQ(model.meshing.tetrahedra.seed, 7u);
  EXPECT_FALSE(model.meshing.tetrahedra.exude);
  EXPECT_EQ(model.material.young_modulus, 2e6);
  ASSERT_EQ(model.anchors.size(), 2u);
  EXPECT_EQ(model.anchors[0].kind, AnchorRegion::Kind::box);
  EXPECT_TRUE(model.anchors[0].max.isApprox(Eigen::Vector3d(0.01, 0.02, 0.03)));
  EXPECT_TRUE(model.anchors[0].contains(Eigen::Vector3d(0.005, 0.02, 0.0)));
  EXPECT_FALSE(model.anchors[0].contains(Eigen::Vector3d(0.005, 0.021, 0.0)));
  EXPECT_EQ(model.anchors[1].kind, AnchorRegion::Kind::half_space);
  EXPECT_TRUE(model.anchors[1].normal.isApprox(Eigen::Vector3d::UnitZ()));  // normalized
  EXPECT_TRUE(model.anchors[1].contains(Eigen::Vector3d(5, 5, 0.04)));
  EXPECT_FALSE(model.anchors[1].contains(Eigen::Vector3d(0, 0, 0.039)));
  EXPECT_EQ(model.basis.modal.modes.num_modes, 4);
  EXPECT_EQ(model.basis.basis_size(), 10);
  EXPECT_EQ(model.basis.modal.modes.mass, reduced::MassLumping::lumped);
  EXPECT_EQ(model.basis.modal.metric, reduced::PcaMetric::euclidean);
  EXPECT_EQ(model.basis.modal.modes.tolerance, 1e-9);
  EXPECT_EQ(model.basis.modal.modes.max_restarts, 10);
  EXPECT_EQ(model.integrator.newmark.time_step, 0.002);
  EXPECT_EQ(model.integrator.newmark.mass_damping, 0.5);
  EXPECT_EQ(model.integrator.newmark.stiffness_damping, 0.01);
  EXPECT_EQ(model.integrator.max_newton_iterations, 3);
  EXPECT_EQ(model.integrator.acceleration_limit, 1e4);

  EXPECT_EQ(tool.field.distance.cells, 64);
  EXPECT_EQ(tool.field.distance.box_expansion, 2.0);
  EXPECT_EQ(tool.field.distance.exact_band, 4.0);
  EXPECT_EQ(tool.field.deformed.proxies, 30);
  EXPECT_EQ(tool.field.deformed.neighbours, 6);
  EXPECT_EQ(tool.field.deformed.seed, std::numeric_limits<std::uint64_t>::max());
  EXPECT_EQ(tool.pointshell.method, PointshellMethod::vertices);
  EXPECT_EQ(tool.pointshell.nested.schedule.first_level_size, 4);
  EXPECT_EQ(tool.pointshell.nested.schedule.growth, 3);
  EXPECT_EQ(tool.pointshell.nested.schedule.max_levels, 2);
  EXPECT_EQ(tool.pointshell.nested.seed, 3u);
  EXPECT_EQ(s.objects[1].scale, 2.0);

  EXPECT_EQ(s.haptic.front().role, contact::HapticObject::distance_field);
  EXPECT_FALSE(s.haptic.front().grasp_at_centre);
  EXPECT_TRUE(s.haptic.front().grasp_point.isApprox(Eigen::Vector3d(0.01, 0.02, 0.03)));

  EXPECT_EQ(s.contact.haptic_object, contact::HapticObject::distance_field);
  EXPECT_EQ(s.contact.stiffness, 2000.0);
  EXPECT_EQ(s.contact.scaling_count, 5.0);
  EXPECT_EQ(s.contact.max_level, 3);
  EXPECT_EQ(s.contact.gradient, contact::ContactGradient::normal_direction);
  EXPECT_EQ(s.contact.onset_voxels, 0.3);
  EXPECT_EQ(s.contact.onset_depth, 1e-4);
  EXPECT_EQ(s.contact.degradation.mode, contact::DegradationOptions::Mode::time_budget);
  EXPECT_EQ(s.contact.degradation.budget_microseconds, 100.0);
  EXPECT_EQ(s.contact.degradation.cold_fraction, 0.5);
  EXPECT_EQ(s.contact.degradation.contact_weight, 1.5);
  EXPECT_TRUE(s.contact.coherence.enabled);
  EXPECT_EQ(s.contact.coherence.max_field_deformation, 0.003);
  EXPECT_EQ(s.contact.coherence.max_skip, 64);
  EXPECT_EQ(s.contact.friction.static_coefficient, 0.4);
  EXPECT_EQ(s.contact.friction.kinetic_coefficient, 0.3);
  EXPECT_EQ(s.contact.friction.stick_distance, 2e-4);
  ASSERT_EQ(s.pairs.size(), 1U);
  EXPECT_EQ(s.pairs[0].objects[0], "wall");
  EXPECT_EQ(s.pairs[0].object_indices[0], 1);
  EXPECT_EQ(s.pairs[0].object_indices[1], 0);
  // Keys a pair leaves out keep the scene's friction.
  EXPECT_EQ(s.pairs[0].friction.static_coefficient, 0.7);
  EXPECT_EQ(s.pairs[0].friction.kinetic_coefficient, 0.3);
  EXPECT_EQ(s.pairs[0].friction.stick_distance, 2e-4);

  EXPECT_EQ(s.coupling.stiffness, 400.0);
  EXPECT_EQ(s.coupling.static_damping, 0.25);
  EXPECT_EQ(s.coupling.object_radius, 0.05);
  EXPECT_EQ(s.coupling.rotation_length, 0.1);
  EXPECT_EQ(s.coupling.period, 1.0 / 500.0);

  const DeviceDescription& device = s.haptic.front().device;
  EXPECT_EQ(device.type, DeviceType::simulated_operator);
  ASSERT_EQ(device.keyframes.size(), 2u);
  EXPECT_EQ(device.keyframes[1].time, 1.0);
  EXPECT_TRUE(device.keyframes[1].pose.position.isApprox(Eigen::Vector3d(0, 0, -0.01)));
  EXPECT_NEAR(device.keyframes[1].pose.orientation.angularDistance(Eigen::Quaterniond::Identity()),
              10.0 * std::numbers::pi / 180.0, 1e-12);
  EXPECT_EQ(device.simulated_operator.hand.stiffness, 200.0);
  EXPECT_EQ(device.simulated_operator.hand.mass, haptic::HandModel{}.mass);
  EXPECT_EQ(device.simulated_operator.device.mass, 0.2);
  EXPECT_EQ(device.simulated_operator.substeps, 4);
  EXPECT_FALSE(device.simulated_operator.start_at_target);
  EXPECT_EQ(device.simulated_operator.initial_pose.position.z(), 0.01);
  // Capabilities: the operator's Phantom-like defaults with the overrides, at the loop's rate.
  const haptic::DeviceCapabilities phantom =
      haptic::SimulatedOperatorOptions::phantom_premium_like();
  EXPECT_EQ(device.capabilities.max_force, 5.0);
  EXPECT_EQ(device.capabilities.output_dof, 3);
  EXPECT_EQ(device.capabilities.max_torque, phantom.max_torque);
  EXPECT_EQ(device.capabilities.nominal_rate, 500.0);
  EXPECT_EQ(device.simulated_operator.capabilities.max_force, 5.0);
  EXPECT_EQ(device.mapping.scale, 2.0);
  EXPECT_EQ(device.mapping.offset.position.z(), 0.5);
  EXPECT_EQ(device.mapping.force_scale, 0.5);
  EXPECT_EQ(device.safety.max_force, 4.0);
  EXPECT_EQ(device.safety.index_button, 0);
  EXPECT_FALSE(device.safety.index_orientation);
  EXPECT_TRUE(device.safety.passivity_control);
  EXPECT_EQ(device.safety.passivity_max_damping, 3.0);
  EXPECT_EQ(device.safety.passivity_max_rotational_damping, 0.01);

  EXPECT_EQ(s.loop.rate_hz, 500.0);
  EXPECT_EQ(s.duration, 2.5);
  EXPECT_TRUE(s.loop.realtime_priority);
  EXPECT_EQ(s.loop.priority, 90);
  EXPECT_EQ(s.loop.cpu, 1);

  // The preparation's threads.
  Json threaded = minimal_scene();
  threaded["threads"] = 3;
  EXPECT_EQ(parse(threaded).threads, 3);
  EXPECT_EQ(parse(minimal_scene()).threads, 0);

  // The node-count mode's own settings.
  Json counted = minimal_scene();
  counted["contact"] = {
      {"degradation", {{"mode", "node_count"}, {"warm_threshold", 900}, {"cold_fraction", 0.5}}}};
  const contact::DegradationOptions d = parse(counted).contact.degradation;
  EXPECT_EQ(d.mode, contact::DegradationOptions::Mode::node_count);
  EXPECT_EQ(d.warm_threshold, 900.0);
  EXPECT_EQ(d.cold_fraction, 0.5);
}

// Free bodies (issue 20): each object's "dynamics", the scene's "dynamics" settings, a hand's
// grasp button and an operator's button presses; left out, the library's defaults.
TEST(SceneDescription, FreeBodiesTheirSettingsAndGrasping) {
  const SceneDescription plain = parse(minimal_scene());
  EXPECT_FALSE(plain.objects[0].is_dynamic());
  EXPECT_EQ(plain.haptic.front().grasp_button, -1);
  const haptic::DynamicsOptions defaults;
  EXPECT_EQ(plain.dynamics.gravity, defaults.gravity);
  EXPECT_EQ(plain.dynamics.contact_damping, defaults.contact_damping);
  EXPECT_EQ(plain.dynamics.sleep_speed, defaults.sleep_speed);
  EXPECT_EQ(plain.dynamics.sleep_time, defaults.sleep_time);
  EXPECT_EQ(plain.dynamics.time_step, 1.0 / plain.loop.rate_hz);

  Json scene = minimal_scene();
  scene["objects"].push_back(Json::parse(R"({
    "name": "box", "mesh": "cube.off", "roles": ["pointshell", "distance_field"],
    "dynamics": {"density": 800, "velocity": [1, 2, 3], "angular_velocity": [4, 5, 6]}})"));
  scene["objects"].push_back(Json::parse(R"({
    "name": "ball", "mesh": "cube.off", "roles": ["pointshell"], "dynamics": {"mass": 0.25}})"));
  scene["objects"].push_back(Json::parse(R"({
    "name": "pebble", "mesh": "cube.off", "roles": ["pointshell"], "dynamics": {}})"));
  scene["dynamics"] = Json::parse(R"({"gravity": [0, -9.8, 0], "contact_damping": 0.01,
                                      "sleep_speed": 0.002, "sleep_time": 0.5})");
  scene["haptic"]["grasp_button"] = 2;
  scene["loop"] = {{"rate_hz", 2000}};
  scene["device"] = Json::parse(R"({"type": "operator", "keyframes": [
    {"time": 0, "position": [0, 0, 0]}, {"time": 1, "position": [0, 0, 0], "buttons": 4}]})");
  const SceneDescription s = parse(scene);
  ASSERT_TRUE(s.objects[2].dynamics.has_value());
  EXPECT_EQ(s.objects[2].dynamics->density, 800.0);
  EXPECT_FALSE(s.objects[2].dynamics->mass.has_value());
  EXPECT_EQ(s.objects[2].dynamics->velocity, Eigen::Vector3d(1, 2, 3));
  EXPECT_EQ(s.objects[2].dynamics->angular_velocity, Eigen::Vector3d(4, 5, 6));
  EXPECT_EQ(s.objects[3].dynamics->mass, 0.25);
  EXPECT_EQ(s.objects[4].dynamics->density, 1000.0);
  EXPECT_EQ(s.objects[4].dynamics->velocity, Eigen::Vector3d::Zero());
  EXPECT_EQ(s.dynamics.gravity, Eigen::Vector3d(0, -9.8, 0));
  EXPECT_EQ(s.dynamics.contact_damping, 0.01);
  EXPECT_EQ(s.dynamics.sleep_speed, 0.002);
  EXPECT_EQ(s.dynamics.sleep_time, 0.5);
  EXPECT_EQ(s.dynamics.time_step, 1.0 / 2000.0);
  EXPECT_EQ(s.haptic.front().grasp_button, 2);
  EXPECT_EQ(s.haptic.front().device.keyframes[0].buttons, 0u);
  EXPECT_EQ(s.haptic.front().device.keyframes[1].buttons, 4u);
}

TEST(SceneDescription, DerivedDefaults) {
  // With both roles the held object plays the distance field (the thesis's convention).
  Json scene = minimal_scene();
  scene["objects"][0]["roles"] = {"distance_field", "pointshell"};
  scene["objects"][1]["roles"] = {"pointshell"};
  EXPECT_EQ(parse(scene).haptic.front().role, contact::HapticObject::distance_field);

  // Without derivatives, r defaults to k.
  scene = reduced_scene();
  scene["objects"][0]["model"]["basis"] = {{"k", 7}, {"modal_derivatives", false}};
  EXPECT_EQ(parse(scene).objects[0].model.basis.basis_size(), 7);

  // "points" picks n₀ = round(3N / (4ᴸ − 1)).
  scene = minimal_scene();
  scene["objects"][0]["pointshell"] = {{"points", 262229}, {"levels", 5}};
  EXPECT_EQ(parse(scene).objects[0].pointshell.repulsion.first_level_points, 769);
  scene["objects"][0]["pointshell"] = {{"points", 1}, {"levels", 3}};
  EXPECT_EQ(parse(scene).objects[0].pointshell.repulsion.first_level_points, 1);

  // Integral floats count as integers; the loop rate sets the periods.
  scene = reduced_scene();
  scene["objects"][1]["field"] = {{"cells", 64.0}};
  scene["loop"] = {{"rate_hz", 2000}};
  const SceneDescription s = parse(scene);
  EXPECT_EQ(s.objects[1].field.distance.cells, 64);
  EXPECT_EQ(s.coupling.period, 0.0005);
  EXPECT_EQ(s.objects[0].model.integrator.newmark.time_step, 0.0005);
  EXPECT_EQ(s.haptic.front().device.capabilities.nominal_rate, 2000.0);
}

TEST(SceneDescription, SketchAndSimulationDataBases) {
  Json scene = reduced_scene();
  Json& model = scene["objects"][0]["model"];
  model["anchors"] = Json::parse(R"([{"type": "box", "min": [0, 0, 0], "max": [1, 1, 0.1]}])");
  model["basis"] = Json::parse(R"({"method": "sketch", "r": 2, "loads": "loads.csv",
      "force_separation": 0.5, "static_solve": {"load_steps": 4}, "skip_failed_solves": true})");
  SceneDescription s = parse(scene);
  const BasisDescription& sketch = s.objects[0].model.basis;
  EXPECT_EQ(sketch.method, BasisMethod::sketch);
  EXPECT_EQ(sketch.basis_size(), 2);
  EXPECT_EQ(sketch.loads, "loads.csv");
  EXPECT_EQ(sketch.loads_path, (test::test_file("scenes") / "loads.csv").lexically_normal());
  EXPECT_EQ(sketch.sketch.force_separation, 0.5);
  EXPECT_EQ(sketch.sketch.static_solve.load_steps, 4);
  EXPECT_TRUE(sketch.sketch.skip_failed_solves);

  model["basis"] = Json::parse(R"({"method": "simulation_data", "r": 3, "loads": "loads.csv",
      "simulation": {"hold_steps": 20, "release_steps": 30, "snapshot_every": 5}})");
  s = parse(scene);
  const BasisDescription& simulation = s.objects[0].model.basis;
  EXPECT_EQ(simulation.method, BasisMethod::simulation_data);
  EXPECT_EQ(simulation.basis_size(), 3);
  EXPECT_EQ(simulation.simulation.hold_steps, 20);
  EXPECT_EQ(simulation.simulation.release_steps, 30);
  EXPECT_EQ(simulation.simulation.snapshot_every, 5);
}

TEST(SceneDescription, OtherDevices) {
  Json scene = minimal_scene();
  scene["device"] = {
      {"type", "trajectory"}, {"file", "press.csv"}, {"playback", "at_nominal_rate"}};
  SceneDescription s = parse(scene);
  EXPECT_EQ(s.haptic.front().device.type, DeviceType::trajectory);
  EXPECT_EQ(s.haptic.front().device.trajectory_path,
            (test::test_file("scenes") / "press.csv").lexically_normal());
  EXPECT_EQ(s.haptic.front().device.trajectory.playback, haptic::Playback::at_nominal_rate);
  EXPECT_EQ(s.haptic.front().device.capabilities.name,
            haptic::TrajectoryDevice::default_capabilities().name);

  scene["device"] = {{"type", "hardware"}, {"name", "openhaptics"}};
  s = parse(scene);
  EXPECT_EQ(s.haptic.front().device.type, DeviceType::hardware);
  EXPECT_EQ(s.haptic.front().device.hardware_name, "openhaptics");

  scene["device"] = Json::parse(R"({"type": "null", "pose": {"position": [0, 0.1, 0]}})");
  s = parse(scene);
  EXPECT_EQ(s.haptic.front().device.type, DeviceType::null);
  EXPECT_EQ(s.haptic.front().device.null_pose.position.y(), 0.1);
}

TEST(SceneDescription, MeshPaths) {
  // Absolute paths stay; "cgal:NAME" resolves in the CGAL mesh directory.
  Json scene = minimal_scene();
  const std::filesystem::path cube = test::test_file("scenes/cube.off");
  scene["objects"][0]["mesh"] = cube.string();
  scene["objects"][1]["mesh"] = "cgal:dino.off";
  SceneReadOptions options = test_options();
  options.cgal_mesh_dir = test::cgal_mesh("dino.off").parent_path();
  const SceneDescription s = parse_scene(scene.dump(), "scene.json", options);
  EXPECT_EQ(s.objects[0].mesh_path, cube.lexically_normal());
  EXPECT_EQ(s.objects[1].mesh_path, test::cgal_mesh("dino.off").lexically_normal());
  EXPECT_EQ(s.objects[1].mesh, "cgal:dino.off");

  // Without file checks a missing mesh is only resolved.
  scene["objects"][0]["mesh"] = "elsewhere/missing.obj";
  options.check_files = false;
  const SceneDescription unchecked = parse_scene(scene.dump(), "scene.json", options);
  EXPECT_EQ(unchecked.objects[0].mesh_path,
            (test::test_file("scenes") / "elsewhere/missing.obj").lexically_normal());
}

TEST(SceneDescription, ReadSceneResolvesAgainstTheFilesDirectory) {
  const std::filesystem::path file = test::test_file("scenes/minimal.json");
  const SceneDescription scene = read_scene(file);
  EXPECT_EQ(scene.source, file.string());
  EXPECT_EQ(scene.base_directory, file.parent_path().lexically_normal());
  EXPECT_EQ(scene.objects[1].mesh_path, (file.parent_path() / "cube.off").lexically_normal());
}

TEST(SceneDescription, ReadSceneFailures) {
  EXPECT_TRUE(test::throws_with_message<reduced::IoError>(
      [] { read_scene(std::filesystem::path(test::test_data_dir) / "scenes/absent.json"); },
      "absent.json: no such file"));
  // A syntax error names the file as given, the line and nlohmann/json's column.
  const std::filesystem::path file = test::test_file("scenes/syntax_error.json");
  try {
    read_scene(file);
    ADD_FAILURE() << "no error";
  } catch (const SceneError& error) {
    EXPECT_EQ(error.source(), file.string());
    EXPECT_EQ(error.line(), 4);
    EXPECT_EQ(error.column(), 47);  // the end of the unexpected "roles"
    EXPECT_EQ(error.key_path(), "");
    EXPECT_EQ(std::string(error.what()), file.string() + ":4:47: " + error.message());
    EXPECT_NE(error.message().find("JSON syntax error: syntax error while parsing object"),
              std::string::npos)
        << error.message();
  }
}

TEST(SceneDescription, DefaultCgalMeshDirectoryFollowsTheEnvironment) {
  ASSERT_EQ(::setenv("KHZ_CGAL_MESH_DIR", "/somewhere/meshes", 1), 0);
  EXPECT_EQ(default_cgal_mesh_dir(), std::filesystem::path("/somewhere/meshes"));
  ASSERT_EQ(::unsetenv("KHZ_CGAL_MESH_DIR"), 0);
  // This build extracted CGAL's meshes (tests need them), so the fallback knows where.
  EXPECT_TRUE(std::filesystem::exists(default_cgal_mesh_dir() / "dino.off"))
      << default_cgal_mesh_dir();
}

}  // namespace
}  // namespace khz::scene
