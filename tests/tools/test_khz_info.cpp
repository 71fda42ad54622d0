// `khz info FILE` end to end: small real files of every kind, written by the libraries' own
// writers, are described with the figures they were written with; damaged, malformed and
// unknown files exit with status 1 and say why.
#include "khz_command.hpp"

#include <khz/contact/field/distance_grid.hpp>
#include <khz/contact/io/distance_field_file.hpp>
#include <khz/contact/io/distance_field_vti.hpp>
#include <khz/contact/io/point_tree_file.hpp>
#include <khz/contact/io/pointshell_file.hpp>
#include <khz/contact/tree/deformable_point_tree.hpp>
#include <khz/haptic/device/trajectory_file.hpp>
#include <khz/reduced/io/basis_file.hpp>
#include <khz/reduced/io/mesh_file.hpp>
#include <khz/reduced/io/mesh_fingerprint.hpp>
#include <khz/reduced/meshing/box_mesh.hpp>
#include <khz/render/png_file.hpp>
#include <khz/scene/cycle_log.hpp>
#include <khz/test/fixtures.hpp>

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace khz::test {
namespace {

KhzRun khz_info(const std::filesystem::path& file) { return khz("info \"" + file.string() + "\""); }

std::string file_size_text(const std::filesystem::path& file) {
  return std::to_string(std::filesystem::file_size(file)) + " bytes";
}

/// A signed 8³-cell grid from (−0.5, −0.25, 0) with h = 0.125 whose values run from −1 to 1 m
/// in steps of 0.125 (all exact in float and in the printed text).
contact::DistanceGrid small_grid() {
  contact::GridGeometry geometry;
  geometry.origin = Eigen::Vector3d(-0.5, -0.25, 0.0);
  geometry.spacing = 0.125;
  geometry.cells = 8;
  std::vector<float> values(static_cast<std::size_t>(geometry.node_count()));
  for (std::size_t i = 0; i < values.size(); ++i)
    values[i] = 0.125f * static_cast<float>(i % 17) - 1.0f;
  return contact::DistanceGrid(geometry, std::move(values), true);
}

/// Three levels of 2, 4 and 6 points in the box [0, 0.5] × [−0.1, 0] × [0, 0.2], inward normal +z.
contact::Pointshell small_pointshell() {
  contact::Pointshell shell;
  shell.points.resize(12, 3);
  for (int i = 0; i < 12; ++i) {
    shell.points.row(i) << 0.5 * (i % 6) / 5.0, 0.1 * (i % 2) - 0.1, 0.2 * (i / 6);
  }
  shell.normals = contact::PointMatrix::Zero(12, 3);
  shell.normals.col(2).setOnes();
  shell.level_ends = {2, 6, 12};
  return shell;
}

TEST(KhzInfo, DistanceField) {
  const std::filesystem::path file = scratch_file("field.khzsdf");
  contact::write_distance_field(file, small_grid());
  const KhzRun run = khz_info(file);
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_TRUE(has_line_with(run, {"kind:", "distance field file, format version 1"}));
  EXPECT_TRUE(has_line_with(run, {"distances:", "signed (negative inside)"}));
  EXPECT_TRUE(has_line_with(run, {"cells:", "8 per axis (9^3 = 729 nodes)"}));
  EXPECT_TRUE(has_line_with(run, {"spacing:", "0.125 m"}));
  EXPECT_TRUE(has_line_with(run, {"domain:", "min (-0.5, -0.25, 0), max (0.5, 0.75, 1)"}));
  EXPECT_TRUE(has_line_with(run, {"values:", "min -1 m, max 1 m"}));
  EXPECT_TRUE(has_line_with(run, {"memory:", "2916 bytes"}));
  EXPECT_TRUE(has_line_with(run, {"on disk:", file_size_text(file)}));
}

TEST(KhzInfo, DamagedDistanceFieldExitsWithOne) {
  const std::filesystem::path file = scratch_file("damaged.khzsdf");
  contact::write_distance_field(file, small_grid());
  std::string bytes = read_bytes(file);
  bytes[bytes.size() / 2] = static_cast<char>(bytes[bytes.size() / 2] ^ 0x10);
  std::ofstream(file, std::ios::binary) << bytes;
  const KhzRun run = khz_info(file);
  EXPECT_EQ(run.exit_code, 1) << run.output;
  EXPECT_TRUE(has_line_with(run, {"khz: ", "damaged.khzsdf", "checksum mismatch"}));
}

TEST(KhzInfo, Pointshell) {
  const std::filesystem::path file = scratch_file("shell.khzshell");
  contact::write_pointshell(file, small_pointshell());
  const KhzRun run = khz_info(file);
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_TRUE(has_line_with(run, {"kind:", "pointshell file, format version 1"}));
  EXPECT_TRUE(has_line_with(run, {"levels:", "3 (2, 4, 6 points)"}));
  EXPECT_TRUE(has_line_with(run, {"points:", "12"}));
  EXPECT_TRUE(has_line_with(run, {"bounds:", "min (0, -0.1, 0), max (0.5, 0, 0.2)"}));
  EXPECT_TRUE(has_line_with(run, {"on disk:", file_size_text(file)}));
}

TEST(KhzInfo, PointTree) {
  contact::PointTree tree(small_pointshell());
  const Eigen::Index r = 2;
  const std::vector<double> modes(static_cast<std::size_t>(3 * r * tree.num_points()), 0.01);
  const std::string fingerprint = reduced::fingerprint_text(contact::point_tree_fingerprint(tree));
  const std::filesystem::path file = scratch_file("tree.khztree");
  contact::write_deformable_point_tree(
      file, contact::DeformablePointTree(std::move(tree), r, modes, modes));
  const KhzRun run = khz_info(file);
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_TRUE(has_line_with(run, {"kind:", "point tree file, format version 1"}));
  EXPECT_TRUE(has_line_with(run, {"levels:", "3 (2, 4, 6 points)"}));
  EXPECT_TRUE(has_line_with(run, {"points:", "12"}));
  // Tree level i holds every point of pointshell levels 0…i: 2 + 6 + 12 nodes, 8 with children.
  EXPECT_TRUE(has_line_with(run, {"nodes:", "20 (8 with children)"}));
  EXPECT_TRUE(has_line_with(run, {"modes r:", "2"}));
  EXPECT_TRUE(has_line_with(run, {"fingerprint:", fingerprint}));
  EXPECT_TRUE(has_line_with(run, {"on disk:", file_size_text(file)}));
}

TEST(KhzInfo, MeshesAndBasis) {
  const reduced::VolumeMesh mesh = reduced::box_tet_mesh(
      Eigen::Vector3d::Zero(), Eigen::Vector3d(1.0, 2.0, 3.0), Eigen::Vector3i(2, 1, 1));
  const std::filesystem::path mesh_file = scratch_file("box.msh");
  reduced::write_volume_mesh(mesh_file, mesh);
  const KhzRun volume = khz_info(mesh_file);
  ASSERT_EQ(volume.exit_code, 0) << volume.output;
  EXPECT_TRUE(has_line_with(volume, {"vertices:", "12"}));
  EXPECT_TRUE(has_line_with(volume, {"elements:", "12 tetrahedra"}));
  EXPECT_TRUE(has_line_with(volume, {"bounds:", "min (0, 0, 0), max (1, 2, 3)"}));

  reduced::Basis basis;
  basis.vectors = Eigen::MatrixXd::Constant(3 * mesh.num_vertices(), 3, 0.5);
  basis.fixed_vertices = {0, 1};
  basis.recipe = "a test basis";
  const std::filesystem::path basis_file = scratch_file("box.khzbasis");
  reduced::write_basis(basis_file, basis, mesh);
  const KhzRun described = khz_info(basis_file);
  ASSERT_EQ(described.exit_code, 0) << described.output;
  EXPECT_TRUE(has_line_with(described, {"basis size r:", "3"}));
  EXPECT_TRUE(has_line_with(described, {"fixed vertices:", "2"}));
  EXPECT_TRUE(has_line_with(
      described, {"fingerprint:", reduced::fingerprint_text(reduced::mesh_fingerprint(mesh))}));
  EXPECT_TRUE(has_line_with(described, {"recipe:", "a test basis"}));

  const KhzRun surface = khz_info(test_file("scenes/cube.off"));
  ASSERT_EQ(surface.exit_code, 0) << surface.output;
  EXPECT_TRUE(has_line_with(surface, {"closed:", "yes"}));
}

/// A scene with a rigid field "wall" and a reduced random pointshell "tool" driven by a
/// trajectory, its loop at 500 Hz for 2.5 s; `tool_basis` is the tool's model.basis.
std::filesystem::path write_scene(const std::string& tool_basis) {
  const std::string mesh = test_file("scenes/cube.off").string();
  const std::string trajectory = test_file("scenes/press.csv").string();
  const std::filesystem::path scene = scratch_file("scene.json");
  std::ofstream(scene) << R"({"objects": [
    {"name": "wall", "mesh": ")"
                       << mesh << R"(", "roles": ["distance_field"], "field": {"cells": 16}},
    {"name": "tool", "mesh": ")"
                       << mesh << R"(", "roles": ["pointshell"],
     "pointshell": {"method": "random", "points": 200, "levels": 3},
     "model": {"type": "reduced",
               "material": {"young_modulus": 1e5, "poisson_ratio": 0.3, "density": 1000},
               "basis": )"
                       << tool_basis << R"(}}],
  "haptic": {"object": "tool", "grasp_point": [0, 0, 0.01]},
  "device": {"type": "trajectory", "file": ")"
                       << trajectory << R"("},
  "loop": {"rate_hz": 500, "duration": 2.5}})";
  return scene;
}

TEST(KhzInfo, Scene) {
  const KhzRun run = khz_info(write_scene(R"({"method": "modes", "k": 4, "r": 6})"));
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_TRUE(has_line_with(run, {"kind:", "scene file, version 2"}));
  EXPECT_TRUE(has_line_with(run, {"objects:", "2"}));
  EXPECT_TRUE(has_line_with(run, {"object:", "wall"}));
  EXPECT_TRUE(has_line_with(run, {"model:", "rigid"}));
  EXPECT_TRUE(has_line_with(run, {"roles:", "distance_field"}));
  EXPECT_TRUE(has_line_with(run, {"field:", "16 cells per axis"}));
  EXPECT_TRUE(has_line_with(run, {"object:", "tool"}));
  EXPECT_TRUE(has_line_with(run, {"roles:", "pointshell"}));
  EXPECT_TRUE(has_line_with(run, {"model:", "reduced, modes basis, r = 6, k = 4"}));
  EXPECT_TRUE(has_line_with(run, {"pointshell:", "random, at most 3 levels"}));
  // A random pointshell needs no field; the rigid wall needs nothing but its field.
  EXPECT_TRUE(has_line_with(run, {"products:", "pointshell, reduced_model"}));
  EXPECT_TRUE(has_line_with(run, {"products:", "distance_field"}));
  EXPECT_TRUE(has_line_with(
      run, {"haptic:", "tool as its pointshell, grasped at (0, 0, 0.01) m (body frame)"}));
  EXPECT_TRUE(has_line_with(run, {"device:", "trajectory, file ", "press.csv"}));
  EXPECT_TRUE(has_line_with(run, {"loop:", "500 Hz, for 2.5 s"}));
}

TEST(KhzInfo, MalformedSceneExitsWithOneNamingTheKey) {
  const KhzRun run = khz_info(write_scene(R"({"method": "modes", "k": 4, "r": -3})"));
  EXPECT_EQ(run.exit_code, 1) << run.output;
  EXPECT_TRUE(has_line_with(run, {"khz: ", "scene.json: objects[1].model.basis.r: "}));
}

TEST(KhzInfo, Trajectory) {
  std::vector<haptic::TrajectorySample> samples(3);
  samples[0].time = 0.5;
  samples[1].time = 0.75;
  samples[1].pose.position = Eigen::Vector3d(0.25, -0.5, 0.125);
  samples[2].time = 1.5;
  samples[2].pose.position = Eigen::Vector3d(-0.25, 0.0, 0.5);
  const std::filesystem::path file = scratch_file("path.csv");
  haptic::write_trajectory(file, samples);
  const KhzRun run = khz_info(file);
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_TRUE(has_line_with(run, {"samples:", "3"}));
  EXPECT_TRUE(has_line_with(run, {"duration:", "1 s (t = 0.5 .. 1.5 s)"}));
  EXPECT_TRUE(has_line_with(run, {"positions:", "min (-0.25, -0.5, 0), max (0.25, 0, 0.5)"}));
  EXPECT_TRUE(has_line_with(run, {"on disk:", file_size_text(file)}));
}

TEST(KhzInfo, CsvThatIsNoTrajectoryExitsWithOne) {
  const std::filesystem::path file = scratch_file("loads.csv");
  std::ofstream(file) << "load,vertex,fx,fy,fz\n0,1,0,0,-2\n";
  const KhzRun run = khz_info(file);
  EXPECT_EQ(run.exit_code, 1) << run.output;
  EXPECT_TRUE(
      has_line_with(run, {"khz: ", "loads.csv is not a device trajectory", "loads.csv:1: "}));
}

TEST(KhzInfo, CycleLog) {
  std::vector<scene::CycleRow> rows(4);
  for (std::size_t i = 0; i < rows.size(); ++i) {
    rows[i].time = 0.002 * static_cast<double>(i);
    rows[i].cycle_us = 10.0 * static_cast<double>(i + 1);
  }
  rows[2].contacts = 7;
  rows[2].nodes = 99;
  rows[2].level = 3;
  rows[2].force = Eigen::Vector3d(0.0, 3.0, 4.0);
  rows[3].ok = false;
  const std::filesystem::path file = scratch_file("cycles.csv");
  scene::write_cycle_csv(rows, file);
  const KhzRun run = khz_info(file);
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_TRUE(has_line_with(run, {"kind:", "khz run cycle log"}));
  EXPECT_TRUE(has_line_with(run, {"cycles:", "4 (0.008 s at 500 Hz), 1 in contact"}));
  EXPECT_TRUE(has_line_with(run, {"us per cycle:", "mean 25, p99 40, max 40"}));
  EXPECT_TRUE(has_line_with(run, {"contact:", "max 7 points, max 99 nodes, deepest level 3"}));
  EXPECT_TRUE(has_line_with(run, {"forces:", "max 5 N contact"}));
  EXPECT_TRUE(has_line_with(run, {"failed cycles:", "1"}));
}

// A log written before the penetration, residual, energy and sliding columns existed is still a
// cycle log to khz info, as it is to read_cycle_csv().
TEST(KhzInfo, CycleLogOfAnEarlierVersion) {
  std::vector<scene::CycleRow> rows(3);
  for (std::size_t i = 0; i < rows.size(); ++i) rows[i].time = 0.001 * static_cast<double>(i);
  rows[1].contacts = 5;
  const std::filesystem::path current = scratch_file("current_cycles.csv");
  scene::write_cycle_csv(rows, current);
  const std::filesystem::path file = scratch_file("earlier_cycles.csv");
  {
    std::ifstream in(current);
    std::ofstream out(file);
    for (std::string line; std::getline(in, line);) {
      for (int column = 0; column < 5; ++column) line.erase(line.rfind(','));
      out << line << "\n";
    }
  }
  const KhzRun run = khz_info(file);
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_TRUE(has_line_with(run, {"kind:", "khz run cycle log"}));
  EXPECT_TRUE(has_line_with(run, {"cycles:", "3 (0.003 s at 1000 Hz), 1 in contact"}));
}

TEST(KhzInfo, PngImage) {
  const std::filesystem::path file = scratch_file("picture.png");
  render::write_png(render::Image(17, 9), file);
  const KhzRun run = khz_info(file);
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_TRUE(has_line_with(run, {"width:", "17 pixels"}));
  EXPECT_TRUE(has_line_with(run, {"height:", "9 pixels"}));
}

TEST(KhzInfo, ParaViewSeriesIsNamed) {
  const std::filesystem::path file = scratch_file("run.pvd");
  std::ofstream(file) << "<VTKFile type=\"Collection\"/>\n";
  const KhzRun run = khz_info(file);
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_TRUE(has_line_with(run, {"kind:", "khz run frame series for ParaView"}));
}

TEST(KhzInfo, ParaViewFieldIsNamedAndSized) {
  const std::filesystem::path file = scratch_file("field.vti");
  contact::write_distance_field_vti(file, small_grid());
  const KhzRun run = khz_info(file);
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_TRUE(has_line_with(run, {"kind:", "ParaView"}));
  EXPECT_TRUE(has_line_with(run, {"contents:", "no reader"}));
  EXPECT_TRUE(has_line_with(run, {"on disk:", file_size_text(file)}));
}

TEST(KhzInfo, UnknownExtensionExitsWithOneListingTheKnownOnes) {
  const std::filesystem::path file = scratch_file("notes.xyz");
  std::ofstream(file) << "text\n";
  const KhzRun run = khz_info(file);
  EXPECT_EQ(run.exit_code, 1) << run.output;
  EXPECT_TRUE(has_line_with(run, {"khz: ", "notes.xyz", "\".xyz\"", ".khzsdf", ".khzshell",
                                  ".khztree", ".json", ".csv", ".png", ".vti"}));
}

}  // namespace
}  // namespace khz::test
