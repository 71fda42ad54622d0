#include <khz/reduced/errors.hpp>
#include <khz/reduced/io/gmsh.hpp>
#include <khz/test/fixtures.hpp>

#include <gtest/gtest.h>

#include <string>

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

TEST(Gmsh, RoundTripIsBitExact) {
  VolumeMesh grouped = hex_pair();
  grouped.vertices(5, 1) = 1.0 / 3;
  grouped.vertices(7, 2) = -4.9e-324;
  VolumeMesh ungrouped = grouped;
  ungrouped.element_groups.resize(0);
  const VolumeMesh tets = parse_file("volume/sparse_tags.msh");
  for (const VolumeMesh& mesh : {grouped, ungrouped, tets}) {
    const VolumeMesh back = parse_gmsh(format_gmsh(mesh), "m.msh");
    EXPECT_EQ(back.element_type, mesh.element_type);
    EXPECT_EQ(back.vertices, mesh.vertices);
    EXPECT_EQ(back.elements, mesh.elements);
    EXPECT_EQ(back.element_groups, mesh.element_groups);
  }
}

TEST(Gmsh, MalformedFilesThrowParseErrorsWithLocation) {
  const test::MalformedFile cases[] = {
      {"empty.msh", "empty.msh:1: file ends early: expected $MeshFormat"},
      {"not_msh.msh", "not_msh.msh:1: expected $MeshFormat, found $Mesh"},
      {"version_41.msh", "version_41.msh:2: unsupported MSH version 4.1 (expected 2.2 ASCII)"},
      {"binary.msh",
       "binary.msh:2: binary MSH (file-type 1) is not supported: only ASCII (file-type 0) is"},
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
       "(type 4) and hexahedra (type 5) are supported"},
      {"unknown_type.msh", "unknown_type.msh:13: element 1 has unsupported type 16"},
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
  };
  test::expect_corpus_rejected("malformed/gmsh", cases, [](const std::filesystem::path& file) {
    parse_gmsh(test::read_bytes(file), file.filename().string());
  });
}

}  // namespace
}  // namespace khz::reduced
