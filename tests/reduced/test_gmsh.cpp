#include <khz/reduced/errors.hpp>
#include <khz/reduced/io/gmsh.hpp>
#include <khz/reduced/io/mesh_file.hpp>
#include <khz/reduced/mesh/element_quality.hpp>
#include <khz/reduced/meshing/box_mesh.hpp>
#include <khz/test/external_program.hpp>
#include <khz/test/fixtures.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

namespace khz::reduced {
namespace {

VolumeMesh parse_file(const std::string& name) {
  return parse_gmsh(test::read_bytes(test::test_file(name)), name);
}

const std::string header = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n";
const std::string four_nodes = "$Nodes\n4\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n$EndNodes\n";

/// The 2×1×1 grid of unit hexahedra [0,2]×[0,1]×[0,1], in groups 3 and 0.
VolumeMesh hex_pair() {
  VolumeMesh mesh;
  mesh.element_type = ElementType::hexahedron;
  mesh.vertices.resize(12, 3);
  for (int z = 0; z < 2; ++z) {
    for (int y = 0; y < 2; ++y) {
      for (int x = 0; x < 3; ++x) mesh.vertices.row(6 * z + 3 * y + x) << x, y, z;
    }
  }
  mesh.elements.resize(2, 8);
  for (int x = 0; x < 2; ++x) {
    mesh.elements.row(x) << x, x + 1, x + 4, x + 3, x + 6, x + 7, x + 10, x + 9;
  }
  mesh.element_groups.resize(2);
  mesh.element_groups << 3, 0;
  return mesh;
}

TEST(Gmsh, KeepsTheHexahedronAndDropsBoundaryEntities) {
  const VolumeMesh mesh = parse_file("volume/hex_boundary.msh");
  EXPECT_EQ(mesh.element_type, ElementType::hexahedron);
  ASSERT_EQ(mesh.elements.rows(), 1);
  ASSERT_EQ(mesh.elements.cols(), 8);
  EXPECT_EQ(mesh.elements.row(0),
            (Eigen::Matrix<int, 1, 8>() << 0, 1, 2, 3, 4, 5, 6, 7).finished());
  EXPECT_EQ(mesh.element_groups, Eigen::VectorXi::Constant(1, 7));
}

TEST(Gmsh, KeepsNodesOnlyBoundaryElementsUse) {
  const VolumeMesh mesh = parse_file("volume/hex_boundary.msh");
  ASSERT_EQ(mesh.num_vertices(), 9);
  EXPECT_EQ(mesh.vertices.row(8), Eigen::RowVector3d(0.5, 0.5, -0.25));
}

TEST(Gmsh, MapsArbitraryNodeTagsToFileOrder) {
  const VolumeMesh mesh = parse_file("volume/sparse_tags.msh");
  ElementMatrix elements(2, 4);
  elements << 0, 1, 2, 3, 1, 2, 3, 4;
  ASSERT_EQ(mesh.num_vertices(), 6);
  ASSERT_EQ(mesh.elements.rows(), 2);
  ASSERT_EQ(mesh.elements.cols(), 4);
  EXPECT_EQ(mesh.elements, elements);
  EXPECT_EQ(mesh.vertices.row(2), Eigen::RowVector3d(0, 1, 0));
}

TEST(Gmsh, HasNoGroupsWhenNoElementHasTags) {
  EXPECT_EQ(parse_file("volume/sparse_tags.msh").element_groups.size(), 0);
}

TEST(Gmsh, UntaggedElementsJoinGroupZeroWhenOthersAreTagged) {
  const std::string text = header +
                           "$Nodes\n5\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n5 1 1 1\n"
                           "$EndNodes\n$Elements\n2\n1 4 0 1 2 3 4\n2 4 1 6 2 3 4 5\n"
                           "$EndElements\n";
  EXPECT_EQ(parse_gmsh(text, "m.msh").element_groups, Eigen::Vector2i(0, 6));
}

TEST(Gmsh, GroupsIgnoreTagsOfBoundaryElements) {
  const std::string text =
      header + four_nodes + "$Elements\n2\n1 2 2 9 9 1 2 3\n2 4 0 1 2 3 4\n$EndElements\n";
  EXPECT_EQ(parse_gmsh(text, "m.msh").element_groups.size(), 0);
}

TEST(Gmsh, AcceptsOtherMsh2VersionsAndCrLf) {
  for (const char* version : {"2", "2.0", "2.1"}) {
    const std::string text = "$MeshFormat\r\n" + std::string(version) +
                             " 0 8\r\n$EndMeshFormat\r\n" + four_nodes +
                             "$Elements\r\n1\r\n1 4 0 1 2 3 4\r\n$EndElements\r\n";
    EXPECT_EQ(parse_gmsh(text, "m.msh").num_elements(), 1) << version;
  }
}

TEST(Gmsh, WritesMsh22WithOneBasedNodesAndGroupTags) {
  VolumeMesh mesh = hex_pair();
  mesh.vertices(1, 0) = 0.1;
  EXPECT_EQ(format_gmsh(mesh),
            "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n12\n"
            "1 0 0 0\n2 0.1 0 0\n3 2 0 0\n4 0 1 0\n5 1 1 0\n6 2 1 0\n"
            "7 0 0 1\n8 1 0 1\n9 2 0 1\n10 0 1 1\n11 1 1 1\n12 2 1 1\n$EndNodes\n"
            "$Elements\n2\n1 5 2 3 3 1 2 5 4 7 8 11 10\n2 5 2 0 0 2 3 6 5 8 9 12 11\n"
            "$EndElements\n");
}

TEST(Gmsh, WritesNoTagsWithoutGroups) {
  VolumeMesh mesh = hex_pair();
  mesh.element_groups.resize(0);
  const std::string text = format_gmsh(mesh);
  EXPECT_NE(text.find("$Elements\n2\n1 5 0 1 2 5 4 7 8 11 10\n2 5 0 2 3 6 5 8 9 12 11\n"),
            std::string::npos);
}

constexpr GmshFormat all_formats[] = {GmshFormat::msh22_ascii, GmshFormat::msh41_ascii,
                                      GmshFormat::msh41_binary};

void expect_same_mesh(const VolumeMesh& actual, const VolumeMesh& expected) {
  EXPECT_EQ(actual.element_type, expected.element_type);
  EXPECT_EQ(actual.vertices, expected.vertices);
  EXPECT_EQ(actual.elements, expected.elements);
  EXPECT_EQ(actual.element_groups, expected.element_groups);
}

TEST(Gmsh, RoundTripIsBitExactInEveryFormat) {
  VolumeMesh grouped = hex_pair();
  grouped.vertices(5, 1) = 1.0 / 3;
  grouped.vertices(7, 2) = -4.9e-324;
  VolumeMesh ungrouped = grouped;
  ungrouped.element_groups.resize(0);
  const VolumeMesh tets = parse_file("volume/sparse_tags.msh");
  // Groups that alternate (one MSH 4.1 block per run) and include 0.
  VolumeMesh interleaved = box_tet_mesh({0, 0, 0}, {1, 0.7, 0.3}, {3, 2, 1});
  interleaved.element_groups.resize(interleaved.num_elements());
  for (Eigen::Index e = 0; e < interleaved.num_elements(); ++e) {
    interleaved.element_groups[e] = static_cast<int>(e % 3);
  }
  VolumeMesh all_zero = interleaved;
  all_zero.element_groups.setZero();
  for (const GmshFormat format : all_formats) {
    for (const VolumeMesh& mesh : {grouped, ungrouped, tets, interleaved, all_zero}) {
      SCOPED_TRACE(static_cast<int>(format));
      expect_same_mesh(parse_gmsh(format_gmsh(mesh, format), "m.msh"), mesh);
    }
  }
}

const std::string msh41_header = "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n";

TEST(Gmsh, ReadsMsh41BlocksWithGroupsFromTheVolumesPhysicalTags) {
  const std::string text =
      msh41_header +
      "$PhysicalNames\n1\n3 7 \"inside\"\n$EndPhysicalNames\n"
      "$Entities\n1 0 1 2\n"
      "1 0 0 0 0\n"                // point 1
      "4 0 0 0 1 1 1 1 3 0\n"      // surface 4: its physical tag is no element group
      "2 0 0 0 1 1 1 2 7 8 1 4\n"  // volume 2: physical tags 7 (its group) and 8
      "5 0 0 0 2 2 2 0 0\n"        // volume 5: no physical tag
      "$EndEntities\n"
      "$Nodes\n3 6 10 60\n"
      "0 1 0 1\n10\n0 0 0\n"
      "2 4 1 3\n20\n30\n40\n1 0 0 0.5 0.5\n0 1 0 0 1\n0 0 1 1 0\n"  // with u, v
      "3 5 0 2\n60\n50\n1 1 1\n2 2 2\n"
      "$EndNodes\n"
      "$Elements\n3 4 1 4\n"
      "2 4 2 1\n1 20 30 40\n"
      "3 2 4 1\n2 10 20 30 40\n"
      "3 5 4 2\n3 20 30 40 60\n4 20 30 40 50\n"
      "$EndElements\n"
      "$NodeData\n1\n\"t\"\n$EndNodeData\n";
  const VolumeMesh mesh = parse_gmsh(text, "m.msh");
  VertexMatrix vertices(6, 3);
  vertices << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 1, 1, 1, 2, 2, 2;
  ElementMatrix elements(3, 4);
  elements << 0, 1, 2, 3, 1, 2, 3, 4, 1, 2, 3, 5;
  EXPECT_EQ(mesh.element_type, ElementType::tetrahedron);
  EXPECT_EQ(mesh.vertices, vertices);
  EXPECT_EQ(mesh.elements, elements);
  EXPECT_EQ(mesh.element_groups, Eigen::Vector3i(7, 0, 0));
}

TEST(Gmsh, Msh41WithoutPhysicalVolumesOrEntitiesHasNoGroups) {
  const std::string nodes_and_elements =
      "$Nodes\n1 4 1 4\n3 1 0 4\n1\n2\n3\n4\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n$EndNodes\n"
      "$Elements\n1 1 1 1\n3 1 4 1\n1 1 2 3 4\n$EndElements\n";
  const std::string untagged = "$Entities\n0 0 0 1\n1 0 0 0 1 1 1 0 0\n$EndEntities\n";
  for (const std::string& entities : {untagged, std::string()}) {
    const VolumeMesh mesh = parse_gmsh(msh41_header + entities + nodes_and_elements, "m.msh");
    EXPECT_EQ(mesh.num_elements(), 1);
    EXPECT_EQ(mesh.element_groups.size(), 0);
  }
}

TEST(Gmsh, ReadsBigEndianMsh41) {
  const VolumeMesh mesh = parse_file("volume/two_tets_41_big_endian.msh");
  VertexMatrix vertices(5, 3);
  vertices << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 1, 1, 1;
  ElementMatrix elements(2, 4);
  elements << 0, 1, 2, 3, 1, 2, 4, 3;
  EXPECT_EQ(mesh.vertices, vertices);
  EXPECT_EQ(mesh.elements, elements);
  EXPECT_EQ(mesh.element_groups, Eigen::Vector2i(5, 5));
}

TEST(Gmsh, WritesMsh41WithOneVolumePerGroupAndOneBlockPerRun) {
  EXPECT_EQ(format_gmsh(hex_pair(), GmshFormat::msh41_ascii),
            msh41_header +
                "$Entities\n0 0 0 2\n1 1 0 0 2 1 1 1 0 0\n2 0 0 0 1 1 1 1 3 0\n$EndEntities\n"
                "$Nodes\n1 12 1 12\n3 1 0 12\n1\n2\n3\n4\n5\n6\n7\n8\n9\n10\n11\n12\n"
                "0 0 0\n1 0 0\n2 0 0\n0 1 0\n1 1 0\n2 1 0\n"
                "0 0 1\n1 0 1\n2 0 1\n0 1 1\n1 1 1\n2 1 1\n$EndNodes\n"
                "$Elements\n2 2 1 2\n3 2 5 1\n1 1 2 5 4 7 8 11 10\n"
                "3 1 5 1\n2 2 3 6 5 8 9 12 11\n$EndElements\n");
}

TEST(Gmsh, WritesMsh41BinaryWithTheEndiannessCheck) {
  const std::string bytes = format_gmsh(hex_pair(), GmshFormat::msh41_binary);
  const std::string start = "$MeshFormat\n4.1 1 8\n";
  ASSERT_EQ(bytes.substr(0, start.size()), start);
  // The int 1, little-endian; then the entity counts 0 0 0 2 as 8-byte size_t.
  const std::string entities = "\n$EndMeshFormat\n$Entities\n";
  EXPECT_EQ(bytes.substr(start.size(), 4 + entities.size() + 32),
            std::string("\1\0\0\0", 4) + entities + std::string(24, '\0') +
                std::string("\2\0\0\0\0\0\0\0", 8));
  EXPECT_TRUE(bytes.ends_with("\n$EndElements\n"));
}

TEST(Gmsh, MalformedFilesThrowParseErrorsWithLocation) {
  const test::MalformedFile cases[] = {
      {"empty.msh", "empty.msh:1: file ends early: expected $MeshFormat"},
      {"not_msh.msh", "not_msh.msh:1: expected $MeshFormat, found $Mesh"},
      {"version_40.msh", "version_40.msh:2: unsupported MSH version 4 (expected 2.2 or 4.1)"},
      {"binary.msh",
       "binary.msh:2: binary MSH 2 (file-type 1) is not supported: save MSH 4.1 or MSH 2.2 "
       "ASCII"},
      {"hostile_count.msh",
       "hostile_count.msh:5: header declares 2000000000 nodes but the rest of the file can hold "
       "at most 2"},
      {"non_numeric.msh", "non_numeric.msh:8: expected y coordinate (a finite number), found 'x'"},
      {"non_finite.msh", "non_finite.msh:7: expected x coordinate (a finite number), found 'inf'"},
      {"missing_end_nodes.msh",
       "missing_end_nodes.msh:10: expected $EndNodes after the 4 nodes the header declares, "
       "found $Elements"},
      {"truncated.msh", "truncated.msh:14: file ends early: expected element 2 of 2"},
      {"undefined_node.msh",
       "undefined_node.msh:13: element 1 uses node tag 99, which $Nodes does not define"},
      {"mixed_types.msh",
       "mixed_types.msh:19: element type 5 (hexahedron) mixed with type 4 (tetrahedron): a mesh "
       "has one element type"},
      {"too_few_nodes.msh",
       "too_few_nodes.msh:13: element 1 has 3 nodes, but type 4 (tetrahedron) has 4"},
      {"quadratic_tet.msh",
       "quadratic_tet.msh:13: element 1 has type 11 (10-node tetrahedron); only linear tetrahedra "
       "(type 4) and hexahedra (type 5) are supported: export linear elements (gmsh -order 1)"},
      {"unknown_type.msh", "unknown_type.msh:13: element 1 has unsupported type 99"},
      {"repeated_node.msh",
       "repeated_node.msh:13: element 1 lists one node twice (as corners 2 and 4)"},
      {"duplicate_node_tag.msh",
       "duplicate_node_tag.msh:10: node tag 2 is defined twice in $Nodes"},
      {"no_volume.msh", "no_volume.msh:14: $Elements holds no tetrahedra or hexahedra"},
      {"negative_group.msh", "negative_group.msh:13: physical group -1 is outside [0, 2147483647]"},
      {"unterminated_section.msh",
       "unterminated_section.msh:7: file ends early: expected $EndPhysicalNames"},
      {"missing_elements.msh", "missing_elements.msh:10: file ends without an $Elements section"},
      {"hostile_tag_count.msh",
       "hostile_tag_count.msh:13: element 1 declares 2000000000 tags but lists only 4 values "
       "after them"},
      // MSH 4.1 ASCII
      {"msh41_node_count_mismatch.msh",
       "msh41_node_count_mismatch.msh:21: the blocks hold 5 nodes, but the $Nodes header "
       "declares 6"},
      {"msh41_element_count_mismatch.msh",
       "msh41_element_count_mismatch.msh:24: element block 1 holds 3 elements, more than the 2 "
       "left of the 2 the $Elements header declares"},
      {"msh41_undefined_node.msh",
       "msh41_undefined_node.msh:26: element 2 uses node tag 9, which $Nodes does not define"},
      {"msh41_second_order.msh",
       "msh41_second_order.msh:24: element block 1 has type 11 (10-node tetrahedron); only "
       "linear tetrahedra (type 4) and hexahedra (type 5) are supported: export linear elements "
       "(gmsh -order 1)"},
      {"msh41_unknown_type.msh",
       "msh41_unknown_type.msh:24: element block 1 has unsupported "
       "type 99"},
      {"msh41_partitioned.msh",
       "msh41_partitioned.msh:8: partitioned meshes ($PartitionedEntities) are not supported: "
       "save the mesh unpartitioned"},
      {"msh41_unknown_volume.msh",
       "msh41_unknown_volume.msh:24: element block 1 belongs to volume entity 2, which "
       "$Entities does not define"},
      {"msh41_surface_block_of_tets.msh",
       "msh41_surface_block_of_tets.msh:24: element block 1 holds volume elements but belongs "
       "to an entity of dimension 2"},
      {"msh41_extra_value.msh",
       "msh41_extra_value.msh:18: unexpected '7' at the end of a node coordinate row"},
      {"msh41_entities_after_elements.msh",
       "msh41_entities_after_elements.msh:24: $Entities comes after $Elements"},
      {"msh41_duplicate_volume.msh",
       "msh41_duplicate_volume.msh:8: volume entity 1 is defined twice in $Entities"},
      {"msh41_duplicate_node_tag.msh",
       "msh41_duplicate_node_tag.msh:21: node tag 3 is defined twice in $Nodes"},
      {"msh41_mixed_types.msh",
       "msh41_mixed_types.msh:26: element type 5 (hexahedron) mixed with type 4 (tetrahedron): "
       "a mesh has one element type"},
      {"msh41_truncated.msh",
       "msh41_truncated.msh:20: file ends early: expected node coordinates 5 of 5"},
      {"msh41_negative_group.msh",
       "msh41_negative_group.msh:6: physical group -1 is outside [0, 2147483647]"},
      {"msh41_no_volume.msh",
       "msh41_no_volume.msh:27: $Elements holds no tetrahedra or "
       "hexahedra"},
      {"msh41_repeated_node.msh",
       "msh41_repeated_node.msh:26: element 2 lists one node twice (as corners 2 and 4)"},
      // MSH 4.1 binary (made by tests/data/malformed/make_binary_cases.py)
      {"msh41_truncated_binary.msh",
       "msh41_truncated_binary.msh: byte 379: file ends early: expected z coordinate (8 bytes, 4 "
       "left)"},
      {"msh41_endianness.msh",
       "msh41_endianness.msh: byte 20: endianness check reads 2, "
       "expected 1"},
      {"msh41_data_size_4.msh",
       "msh41_data_size_4.msh:2: binary MSH with data size 4 is not supported: size_t must take "
       "8 bytes"},
      {"msh41_binary_node_count.msh",
       "msh41_binary_node_count.msh: byte 219: node block 1 holds 5 nodes, more than the 4 left "
       "of the 4 the $Nodes header declares"},
      {"msh41_binary_undefined_node.msh",
       "msh41_binary_undefined_node.msh: byte 524: element 2 uses node tag 9, which $Nodes does "
       "not define"},
      {"msh41_binary_hostile_count.msh",
       "msh41_binary_hostile_count.msh: byte 183: header declares 2000000000 nodes but the rest "
       "of the file can hold at most 11"},
      {"msh41_binary_nan.msh",
       "msh41_binary_nan.msh: byte 347: expected y coordinate (a finite number), found nan"},
      {"msh41_binary_second_order.msh",
       "msh41_binary_second_order.msh: byte 448: element block 1 has type 11 (10-node "
       "tetrahedron); only linear tetrahedra (type 4) and hexahedra (type 5) are supported: "
       "export linear elements (gmsh -order 1)"},
      {"msh41_binary_missing_end.msh",
       "msh41_binary_missing_end.msh: byte 388: expected $EndNodes after the 5 nodes the header "
       "declares, found $EndNode"},
  };
  test::expect_corpus_rejected("malformed/gmsh", cases, [](const std::filesystem::path& file) {
    parse_gmsh(test::read_bytes(file), file.filename().string());
  });
}

// ---- The real Gmsh ----------------------------------------------------------------------
// KHZ_GMSH_PATH comes from find_program() in tests/CMakeLists.txt (empty when not found).

std::string gmsh() { return test::required_program(KHZ_GMSH_PATH, "gmsh", "gmsh"); }

void write_text(const std::filesystem::path& file, const std::string& text) {
  std::ofstream(file, std::ios::binary) << text;
}

/// Runs Gmsh (one thread) and fails with its output unless it succeeds.
std::string run_gmsh(std::vector<std::string> arguments) {
  arguments.insert(arguments.begin(), {"-nt", "1"});
  const test::ProgramRun run = test::run_program(gmsh(), arguments);
  if (run.exit_code != 0) {
    throw std::runtime_error("gmsh exited with " + std::to_string(run.exit_code) + ":\n" +
                             run.output);
  }
  return run.output;
}

/// Meshes the .geo text `geo` as `gmsh -3 <format...> -o <name>.msh <name>.geo` does; returns
/// the .msh path. The .geo holds no `Mesh 3;`: with -3 Gmsh would mesh twice.
std::filesystem::path mesh_with_gmsh(const std::string& geo, const std::string& name,
                                     const std::vector<std::string>& format) {
  const std::filesystem::path script = test::scratch_file(name + ".geo");
  const std::filesystem::path out = test::scratch_file(name + ".msh");
  write_text(script, geo);
  std::vector<std::string> arguments{"-3"};
  arguments.insert(arguments.end(), format.begin(), format.end());
  arguments.insert(arguments.end(), {"-o", out.string(), script.string()});
  run_gmsh(arguments);
  return out;
}

/// What Gmsh itself reads from an MSH file: it merges the file and prints its statistics.
struct GmshCounts {
  Eigen::Index nodes = -1;
  Eigen::Index tetrahedra = -1;
  Eigen::Index hexahedra = -1;
};

GmshCounts gmsh_counts(const std::filesystem::path& msh) {
  const std::filesystem::path script = test::scratch_file(msh.stem().string() + "_counts.geo");
  write_text(script, "Merge \"" + msh.string() +
                         "\";\nPrintf(\"khz-counts %.0f %.0f %.0f\", Mesh.NbNodes, "
                         "Mesh.NbTetrahedra, Mesh.NbHexahedra);\n");
  const std::string output = run_gmsh({"-", script.string()});  // "-": read, then exit
  const std::size_t line = output.find("khz-counts ");
  if (line == std::string::npos) throw std::runtime_error("gmsh printed no counts:\n" + output);
  GmshCounts counts;
  std::istringstream(output.substr(line + 11)) >> counts.nodes >> counts.tetrahedra >>
      counts.hexahedra;
  return counts;
}

void expect_counts(const VolumeMesh& mesh, const GmshCounts& counts) {
  const bool tets = mesh.element_type == ElementType::tetrahedron;
  EXPECT_EQ(mesh.num_vertices(), counts.nodes);
  EXPECT_EQ(mesh.num_elements(), tets ? counts.tetrahedra : counts.hexahedra);
  EXPECT_EQ(tets ? counts.hexahedra : counts.tetrahedra, 0);
}

/// The 1×2×3 box [0,1]×[0,2]×[0,3] as two volumes, z below 1.5 in physical group 7, above in 9.
const std::string two_box_geo = R"(SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 1, 2, 1.5};
Box(2) = {0, 0, 1.5, 1, 2, 1.5};
BooleanFragments{ Volume{1}; Delete; }{ Volume{2}; Delete; }
Physical Volume(7) = Volume In BoundingBox{-1, -1, -1, 2, 3, 1.6};
Physical Volume(9) = Volume In BoundingBox{-1, -1, 1.4, 2, 3, 3.1};
Mesh.CharacteristicLengthMax = 0.4;
)";

// Sums of a few thousand element volumes of size ~1e-3 carry round-off of ~1e-15.
constexpr double round_off = 1e-12;

TEST(GmshProgram, ReadsGmshsTetrahedraAndPhysicalGroupsInEveryFormat) {
  // Gmsh's default (MSH 4.1 ASCII), MSH 4.1 binary, MSH 2.2.
  const std::vector<std::vector<std::string>> formats = {
      {}, {"-format", "msh41", "-bin"}, {"-format", "msh22"}};
  std::vector<VolumeMesh> meshes;
  for (std::size_t f = 0; f < formats.size(); ++f) {
    const auto file = mesh_with_gmsh(two_box_geo, "two_boxes_" + std::to_string(f), formats[f]);
    const VolumeMesh mesh = read_volume_mesh(file);
    SCOPED_TRACE(file.filename().string());
    expect_counts(mesh, gmsh_counts(file));
    EXPECT_NO_THROW(require_valid_elements(mesh));  // Gmsh's orientation is ours
    const QualityReport report = analyze_elements(mesh);
    std::map<int, double> group_volume;
    ASSERT_EQ(mesh.element_groups.size(), mesh.num_elements());
    for (Eigen::Index e = 0; e < mesh.num_elements(); ++e) {
      group_volume[mesh.element_groups[e]] += report.volume[static_cast<std::size_t>(e)];
    }
    ASSERT_EQ(group_volume.size(), 2u);
    EXPECT_NEAR(group_volume[7], 3.0, round_off);
    EXPECT_NEAR(group_volume[9], 3.0, round_off);
    meshes.push_back(mesh);
  }
  // One mesh (one thread makes Gmsh deterministic) in every format; Gmsh's ASCII files hold 16
  // significant digits, its binary files the exact doubles.
  expect_same_mesh(meshes[2], meshes[0]);
  EXPECT_EQ(meshes[1].elements, meshes[0].elements);
  EXPECT_EQ(meshes[1].element_groups, meshes[0].element_groups);
  EXPECT_LE((meshes[1].vertices - meshes[0].vertices).cwiseAbs().maxCoeff(), 1e-15 * 3);
}

/// Boundary faces of a tetrahedral mesh: faces of exactly one tetrahedron.
std::vector<std::array<int, 3>> boundary_faces(const VolumeMesh& mesh) {
  std::map<std::array<int, 3>, int> uses;
  for (Eigen::Index e = 0; e < mesh.num_elements(); ++e) {
    for (int skip = 0; skip < 4; ++skip) {
      std::array<int, 3> face{};
      for (int k = 0, n = 0; k < 4; ++k) {
        if (k != skip) face[static_cast<std::size_t>(n++)] = mesh.elements(e, k);
      }
      std::sort(face.begin(), face.end());
      ++uses[face];
    }
  }
  std::vector<std::array<int, 3>> faces;
  for (const auto& [face, count] : uses) {
    if (count == 1) faces.push_back(face);
  }
  return faces;
}

TEST(GmshProgram, CylinderVolumeIsWithinItsPolygonalApproximation) {
  constexpr double radius = 0.5;  // as in the .geo: the z axis from 0 to 1
  constexpr double height = 1.0;
  const auto file = mesh_with_gmsh(R"(SetFactory("OpenCASCADE");
Cylinder(1) = {0, 0, 0, 0, 0, 1, 0.5};
Mesh.CharacteristicLengthMax = 0.12;
)",
                                   "cylinder", {"-format", "msh41", "-bin"});
  const VolumeMesh mesh = read_volume_mesh(file);
  expect_counts(mesh, gmsh_counts(file));
  EXPECT_NO_THROW(require_valid_elements(mesh));

  // Every node lies in the cylinder (up to round-off), so its volume bounds the mesh's above.
  const auto axis_distance = [&](int v) { return mesh.vertices.row(v).head<2>().norm(); };
  double largest_radius = 0;
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    largest_radius = std::max(largest_radius, axis_distance(v));
  }
  EXPECT_LE(largest_radius, radius * (1 + round_off));
  EXPECT_GE(mesh.vertices.col(2).minCoeff(), -round_off);
  EXPECT_LE(mesh.vertices.col(2).maxCoeff(), height + round_off);
  // Below: a boundary triangle off the caps has corners at distance >= r from the axis within an
  // angle alpha about it, so it keeps r cos(alpha/2) from the axis (the convex hull of an arc of
  // alpha < pi); the boundary misses the cylinder of that radius, which the mesh thus contains.
  const auto cap = [&](int v) {  // 0 bottom, 1 top, -1 neither
    const double z = mesh.vertices(v, 2);
    return std::abs(z) <= round_off ? 0 : std::abs(z - height) <= round_off ? 1 : -1;
  };
  double r = radius;
  double alpha = 0;
  for (const auto& face : boundary_faces(mesh)) {
    if (cap(face[0]) >= 0 && cap(face[0]) == cap(face[1]) && cap(face[1]) == cap(face[2])) {
      continue;  // in a cap's plane, outside the open cylinder 0 < z < height
    }
    for (int a = 0; a < 3; ++a) {
      r = std::min(r, axis_distance(face[static_cast<std::size_t>(a)]));
      for (int b = a + 1; b < 3; ++b) {
        const Eigen::Vector2d p = mesh.vertices.row(face[static_cast<std::size_t>(a)]).head<2>();
        const Eigen::Vector2d q = mesh.vertices.row(face[static_cast<std::size_t>(b)]).head<2>();
        alpha = std::max(alpha, std::atan2(std::abs(p.x() * q.y() - p.y() * q.x()), p.dot(q)));
      }
    }
  }
  EXPECT_GE(r, radius * (1 - round_off));      // boundary nodes lie on the cylinder
  ASSERT_LT(alpha, 2 * std::numbers::pi / 3);  // so the pairwise angle bounds the arc
  const double inner = r * std::cos(alpha / 2);
  const double lower = std::numbers::pi * inner * inner * height;
  const double upper = std::numbers::pi * largest_radius * largest_radius * height;
  const double volume = analyze_elements(mesh).total_volume;
  EXPECT_GE(volume, lower - round_off);
  EXPECT_LE(volume, upper + round_off);
  // The bound is tight enough to mean something: a few percent of the volume.
  EXPECT_LT((upper - lower) / upper, 0.03) << "alpha " << alpha << ", r " << r;
}

TEST(GmshProgram, ReadsExtrudedHexahedra) {
  // A 2×3×4 grid of hexahedra filling [0,1]×[0,2]×[0,3] (Gmsh's built-in kernel, layers and
  // recombination).
  const auto file = mesh_with_gmsh(R"(Point(1) = {0, 0, 0};
line[] = Extrude {1, 0, 0} { Point{1}; Layers{2}; };
face[] = Extrude {0, 2, 0} { Curve{line[1]}; Layers{3}; Recombine; };
Extrude {0, 0, 3} { Surface{face[1]}; Layers{4}; Recombine; }
)",
                                   "hexahedra", {});
  const VolumeMesh mesh = read_volume_mesh(file);
  EXPECT_EQ(mesh.element_type, ElementType::hexahedron);
  EXPECT_EQ(mesh.num_elements(), 24);
  expect_counts(mesh, gmsh_counts(file));
  EXPECT_NO_THROW(require_valid_elements(mesh));
  EXPECT_NEAR(analyze_elements(mesh).total_volume, 6.0, round_off);
}

TEST(GmshProgram, ReadsWhatFormatGmshWrites) {
  VolumeMesh tets = box_tet_mesh({0, 0, 0}, {1, 2, 3}, {2, 3, 4});
  tets.element_groups.resize(tets.num_elements());
  for (Eigen::Index e = 0; e < tets.num_elements(); ++e) {
    tets.element_groups[e] = static_cast<int>(1 + e % 2);
  }
  const VolumeMesh hexes = box_hex_mesh({0, 0, 0}, {1, 2, 3}, {2, 3, 4});
  for (const GmshFormat format : all_formats) {
    for (const VolumeMesh& mesh : {tets, hexes}) {
      const bool tetrahedra = mesh.element_type == ElementType::tetrahedron;
      const auto file = test::scratch_file("written_" + std::to_string(static_cast<int>(format)) +
                                           (tetrahedra ? "_tets.msh" : "_hexes.msh"));
      write_text(file, format_gmsh(mesh, format));
      SCOPED_TRACE(file.filename().string());
      expect_counts(mesh, gmsh_counts(file));
    }
  }
}

}  // namespace
}  // namespace khz::reduced
