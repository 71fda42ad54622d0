#include <khz/reduced/errors.hpp>
#include <khz/reduced/io/mesh_file.hpp>
#include <khz/reduced/io/tetgen.hpp>
#include <khz/reduced/mesh/element_quality.hpp>
#include <khz/test/external_program.hpp>
#include <khz/test/fixtures.hpp>

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace khz::reduced {
namespace {

VolumeMesh parse_files(const std::string& node_name, const std::string& ele_name) {
  return parse_tetgen(test::read_bytes(test::test_file(node_name)), node_name,
                      test::read_bytes(test::test_file(ele_name)), ele_name);
}

/// Two tetrahedra with coordinates whose shortest text is long, tiny or huge.
VolumeMesh two_tets() {
  VolumeMesh mesh;
  mesh.vertices.resize(5, 3);
  mesh.vertices << 0, 0, 0, 0.1, 0, 0, 0, 1.0 / 3, 0, 0, 0, 1e-300, -2.5e17, 1, 1;
  mesh.elements.resize(2, 4);
  mesh.elements << 0, 1, 2, 3, 1, 2, 3, 4;
  mesh.element_groups.resize(2);
  mesh.element_groups << 0, 5;
  return mesh;
}

TEST(Tetgen, ParsesOneBasedFilesWithRegionsCommentsAndMarkers) {
  const VolumeMesh mesh = parse_files("volume/two_tets_1based.node", "volume/two_tets_1based.ele");
  EXPECT_EQ(mesh.element_type, ElementType::tetrahedron);
  VertexMatrix vertices(5, 3);
  vertices << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 1, 1, 1;
  ElementMatrix elements(2, 4);
  elements << 0, 1, 2, 3, 1, 2, 3, 4;
  ASSERT_EQ(mesh.vertices.rows(), 5);
  ASSERT_EQ(mesh.elements.rows(), 2);
  ASSERT_EQ(mesh.elements.cols(), 4);
  EXPECT_EQ(mesh.vertices, vertices);
  EXPECT_EQ(mesh.elements, elements);
  EXPECT_EQ(mesh.element_groups, Eigen::Vector2i(1, 2));
}

TEST(Tetgen, ParsesZeroBasedFilesWithoutGroups) {
  const VolumeMesh mesh = parse_files("volume/two_tets_0based.node", "volume/two_tets_0based.ele");
  ElementMatrix elements(2, 4);
  elements << 0, 1, 2, 3, 1, 2, 3, 4;
  ASSERT_EQ(mesh.vertices.rows(), 5);
  ASSERT_EQ(mesh.elements.rows(), 2);
  ASSERT_EQ(mesh.elements.cols(), 4);
  EXPECT_EQ(mesh.elements, elements);
  EXPECT_EQ(mesh.vertices.row(4), Eigen::RowVector3d(1, 1, 1));
  EXPECT_EQ(mesh.element_groups.size(), 0);
}

TEST(Tetgen, KeepsTheCornersOfTenNodeTetrahedraAndAllNodes) {
  const VolumeMesh mesh = parse_files("volume/tet10.node", "volume/tet10.ele");
  ASSERT_EQ(mesh.elements.rows(), 1);
  ASSERT_EQ(mesh.elements.cols(), 4);
  EXPECT_EQ(mesh.elements.row(0), Eigen::RowVector4i(0, 1, 2, 3));
  EXPECT_EQ(mesh.num_vertices(), 10);  // edge midpoints stay, unreferenced
  EXPECT_EQ(mesh.element_groups, Eigen::VectorXi::Constant(1, 3));
}

TEST(Tetgen, AcceptsRegionAttributesWrittenAsIntegralReals) {
  const std::string node = "4 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n";
  for (const char* region : {"2", "2.0", "2e0", "+2"}) {
    const VolumeMesh mesh =
        parse_tetgen(node, "m.node", std::string("1 4 1\n1 1 2 3 4 ") + region + "\n", "m.ele");
    EXPECT_EQ(mesh.element_groups, Eigen::VectorXi::Constant(1, 2)) << region;
  }
}

TEST(Tetgen, ErrorNamesTheNodeFileAndItsZeroBasedRange) {
  const std::string node = "4 3 0 0\n0 0 0 0\n1 1 0 0\n2 0 1 0\n3 0 0 1\n";
  EXPECT_TRUE(test::throws_with_message(
      [&] { parse_tetgen(node, "dir/m.node", "1 4 0\n0 0 1 2 4\n", "dir/m.ele"); },
      "dir/m.ele:2: tetrahedron 0 uses node 4, but dir/m.node defines nodes 0..3"));
}

TEST(Tetgen, AcceptsCrLfLineEndings) {
  const VolumeMesh mesh = parse_tetgen("4 3 0 0\r\n1 0 0 0\r\n2 1 0 0\r\n3 0 1 0\r\n4 0 0 1\r\n",
                                       "m.node", "1 4 0\r\n1 1 2 3 4\r\n", "m.ele");
  EXPECT_EQ(mesh.num_elements(), 1);
}

TEST(Tetgen, WritesOneBasedFilesWithShortestNumbersAndGroups) {
  const TetgenFiles files = format_tetgen(two_tets());
  EXPECT_EQ(files.node,
            "5 3 0 0\n1 0 0 0\n2 0.1 0 0\n3 0 0.3333333333333333 0\n4 0 0 1e-300\n"
            "5 -2.5e+17 1 1\n");
  EXPECT_EQ(files.ele, "2 4 1\n1 1 2 3 4 0\n2 2 3 4 5 5\n");
}

TEST(Tetgen, WritesNoAttributeWithoutGroups) {
  VolumeMesh mesh = two_tets();
  mesh.element_groups.resize(0);
  EXPECT_EQ(format_tetgen(mesh).ele, "2 4 0\n1 1 2 3 4\n2 2 3 4 5\n");
}

TEST(Tetgen, RoundTripIsBitExact) {
  for (const bool grouped : {true, false}) {
    VolumeMesh mesh = two_tets();
    if (!grouped) mesh.element_groups.resize(0);
    const TetgenFiles files = format_tetgen(mesh);
    const VolumeMesh back = parse_tetgen(files.node, "m.node", files.ele, "m.ele");
    EXPECT_EQ(back.vertices, mesh.vertices);
    EXPECT_EQ(back.elements, mesh.elements);
    EXPECT_EQ(back.element_groups, mesh.element_groups);
  }
}

TEST(Tetgen, WriterRejectsHexahedralMeshes) {
  VolumeMesh mesh;
  mesh.element_type = ElementType::hexahedron;
  EXPECT_TRUE(test::throws_with_message<MeshError>([&] { format_tetgen(mesh); },
                                                   "TetGen files hold tetrahedra only"));
}

struct MalformedCase {
  const char* node;
  const char* ele;
  const char* expected;
};

TEST(Tetgen, MalformedFilesThrowParseErrorsWithLocation) {
  const MalformedCase cases[] = {
      {"empty.node", "ok.ele", "empty.node:1: file ends early: expected the .node header"},
      {"hostile_count.node", "ok.ele",
       "hostile_count.node:1: header declares 2000000000 nodes but the rest of the file can "
       "hold at most 4"},
      {"non_numeric.node", "ok.ele",
       "non_numeric.node:3: expected y coordinate (a finite number), found 'abc'"},
      {"non_finite.node", "ok.ele",
       "non_finite.node:4: expected z coordinate (a finite number), found 'nan'"},
      {"non_consecutive.node", "ok.ele",
       "non_consecutive.node:4: node index 4 breaks consecutive numbering: expected 3"},
      {"bad_first_index.node", "ok.ele",
       "bad_first_index.node:2: first node index is 5; TetGen numbering starts at 0 or 1"},
      {"two_dimensional.node", "ok.ele",
       "two_dimensional.node:1: dimension 2 is not supported: expected 3"},
      {"truncated.node", "ok.ele", "truncated.node:6: file ends early: expected node 4 of 4"},
      {"short_row.node", "ok.ele",
       "short_row.node:3: node row has 4 values, expected 5: index, x, y, z, 1 attribute"},
      {"ok.node", "empty.ele", "empty.ele:1: file ends early: expected the .ele header"},
      {"ok.node", "hostile_count.ele",
       "hostile_count.ele:1: header declares 2000000000 tetrahedra but the rest of the file can "
       "hold at most 1"},
      {"ok.node", "bad_index.ele",
       "bad_index.ele:4: tetrahedron 2 uses node 99, but ok.node defines nodes 1..4"},
      {"ok.node", "eight_nodes.ele",
       "eight_nodes.ele:1: nodes per tetrahedron must be 4 or 10, found 8"},
      {"ok.node", "fractional_region.ele",
       "fractional_region.ele:2: tetrahedron 1 has region attribute 1.5; expected a "
       "non-negative integer"},
      {"ok.node", "negative_region.ele",
       "negative_region.ele:2: tetrahedron 1 has region attribute -1; expected a non-negative "
       "integer"},
      {"ok.node", "extra_rows.ele",
       "extra_rows.ele:3: more tetrahedron rows follow than the 1 the header declares"},
      {"ok.node", "no_tetrahedra.ele", "no_tetrahedra.ele:1: the .ele file declares no tetrahedra"},
      {"ok.node", "repeated_node.ele",
       "repeated_node.ele:2: tetrahedron 1 lists one node twice (as corners 2 and 4)"},
  };
  for (const MalformedCase& c : cases) {
    const std::string dir = "malformed/tetgen/";
    EXPECT_TRUE(test::throws_with_message(
        [&] {
          parse_tetgen(test::read_bytes(test::test_file(dir + c.node)), c.node,
                       test::read_bytes(test::test_file(dir + c.ele)), c.ele);
        },
        c.expected))
        << c.node << " + " << c.ele;
  }
}

// ---- The real TetGen ---------------------------------------------------------------------
// KHZ_TETGEN_PATH comes from find_program() in tests/CMakeLists.txt (empty when not found).

TEST(TetgenProgram, MeshesABoxWeReadWithItsCountsAndVolume) {
  const std::string tetgen = test::required_program(KHZ_TETGEN_PATH, "tetgen", "tetgen");
  // The box [0,1]×[0,2]×[0,3] as a piecewise linear complex: 8 corners, 6 quadrangular facets,
  // no holes, no regions.
  const std::filesystem::path poly = test::scratch_file("box.poly");
  std::ofstream(poly) << "8 3 0 0\n1 0 0 0\n2 1 0 0\n3 1 2 0\n4 0 2 0\n"
                         "5 0 0 3\n6 1 0 3\n7 1 2 3\n8 0 2 3\n"
                         "6 0\n1\n4 1 2 3 4\n1\n4 5 6 7 8\n1\n4 1 2 6 5\n"
                         "1\n4 2 3 7 6\n1\n4 3 4 8 7\n1\n4 4 1 5 8\n0\n0\n";
  const std::filesystem::path ele = test::scratch_file("box.1.ele");
  test::scratch_file("box.1.node");  // clears an earlier run's output
  // -p: mesh the PLC; -q1.4: radius-edge ratio at most 1.4; -a0.05: volume at most 0.05.
  // TetGen writes box.1.node and box.1.ele beside the input and prints its statistics.
  const test::ProgramRun run = test::run_program(tetgen, {"-pq1.4a0.05", poly.string()});
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const auto reported = [&](const std::string& label) {
    const std::size_t at = run.output.find(label);
    Eigen::Index value = -1;
    if (at != std::string::npos) std::istringstream(run.output.substr(at + label.size())) >> value;
    return value;
  };

  const VolumeMesh mesh = read_volume_mesh(ele);
  EXPECT_EQ(mesh.num_elements(), reported("Mesh tetrahedra:")) << run.output;
  EXPECT_EQ(mesh.num_vertices(), reported("Mesh points:")) << run.output;
  EXPECT_GT(mesh.num_elements(), 120);            // the volume limit forces at least 6 / 0.05
  EXPECT_NO_THROW(require_valid_elements(mesh));  // TetGen's orientation is ours
  EXPECT_NEAR(analyze_elements(mesh).total_volume, 6.0, 1e-12);
}

}  // namespace
}  // namespace khz::reduced
