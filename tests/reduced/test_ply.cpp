#include <khz/reduced/errors.hpp>
#include <khz/reduced/io/ply.hpp>
#include <khz/test/allocation_probe.hpp>
#include <khz/test/fixtures.hpp>
#include <khz/test/generated_meshes.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <new>
#include <string>

namespace khz::reduced {
namespace {

constexpr PlyEncoding all_encodings[] = {PlyEncoding::ascii, PlyEncoding::binary_little_endian,
                                         PlyEncoding::binary_big_endian};

TriangleMesh parse_file(const std::filesystem::path& file) {
  return parse_ply(test::read_bytes(file), file.string());
}

/// Appends `value` big-endian, for hand-built binary files.
template <typename T>
void put_big_endian(std::string& out, T value) {
  char bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));
  std::reverse(bytes, bytes + sizeof(T));  // the test host is little-endian
  out.append(bytes, sizeof(T));
}

TEST(Ply, RoundTripsSoupWithColoursExactlyInEveryEncoding) {
  const TriangleMesh mesh = test::random_soup(200, 5);
  for (const PlyEncoding encoding : all_encodings) {
    SCOPED_TRACE(static_cast<int>(encoding));
    const TriangleMesh parsed = parse_ply(format_ply(mesh, encoding), "soup.ply");
    EXPECT_EQ(parsed.vertices, mesh.vertices);
    EXPECT_EQ(parsed.triangles, mesh.triangles);
    ASSERT_EQ(parsed.vertex_colors.rows(), mesh.vertex_colors.rows());
    EXPECT_EQ(parsed.vertex_colors, mesh.vertex_colors);
  }
}

TEST(Ply, RoundTripsUvSphereExactlyInEveryEncoding) {
  const TriangleMesh mesh = test::uv_sphere(24, 12);
  for (const PlyEncoding encoding : all_encodings) {
    SCOPED_TRACE(static_cast<int>(encoding));
    const TriangleMesh parsed = parse_ply(format_ply(mesh, encoding), "sphere.ply");
    EXPECT_EQ(parsed.vertices, mesh.vertices);
    EXPECT_EQ(parsed.triangles, mesh.triangles);
    EXPECT_FALSE(parsed.has_vertex_colors());
  }
}

TEST(Ply, RoundTripsUnitCubeExactlyInEveryEncoding) {
  const TriangleMesh mesh = test::unit_cube_surface();
  for (const PlyEncoding encoding : all_encodings) {
    SCOPED_TRACE(static_cast<int>(encoding));
    const TriangleMesh parsed = parse_ply(format_ply(mesh, encoding), "cube.ply");
    EXPECT_EQ(parsed.vertices, mesh.vertices);
    EXPECT_EQ(parsed.triangles, mesh.triangles);
  }
}

TEST(Ply, WritesDoubleCoordinatesByteColoursAndIntIndices) {
  TriangleMesh mesh = test::unit_square();
  mesh.vertex_colors.setConstant(4, 4, 1.0f);
  EXPECT_EQ(format_ply(mesh, PlyEncoding::ascii),
            "ply\nformat ascii 1.0\ncomment written by Kilohertz\nelement vertex 4\n"
            "property double x\nproperty double y\nproperty double z\nproperty uchar red\n"
            "property uchar green\nproperty uchar blue\nproperty uchar alpha\nelement face 2\n"
            "property list uchar int vertex_indices\nend_header\n"
            "0 0 0 255 255 255 255\n1 0 0 255 255 255 255\n1 1 0 255 255 255 255\n"
            "0 1 0 255 255 255 255\n3 0 1 2\n3 0 2 3\n");
}

TEST(Ply, ReadsCgalColoredTetraSkippingOtherProperties) {
  // Vertices carry normals and an id, faces a colour and a label, and an edge element follows.
  const TriangleMesh mesh = parse_file(test::cgal_mesh("colored_tetra.ply"));
  EXPECT_EQ(mesh.num_vertices(), 4);
  ASSERT_EQ(mesh.num_triangles(), 4);
  EXPECT_EQ(mesh.vertices.row(3), Eigen::RowVector3d(1, 0, 0));
  EXPECT_EQ(mesh.triangles.row(1), Eigen::RowVector3i(0, 3, 1));
  ASSERT_TRUE(mesh.has_vertex_colors());
  EXPECT_EQ(mesh.vertex_colors.row(0), Eigen::RowVector4f(1, 1, 0, 1));
  EXPECT_EQ(mesh.vertex_colors.row(2), Eigen::RowVector4f(128.0f / 255.0f, 0, 1, 1));
}

TEST(Ply, ReadsCgalSphere) {
  const TriangleMesh mesh = parse_file(test::cgal_mesh("sphere.ply"));
  EXPECT_EQ(mesh.num_vertices(), 162);
  EXPECT_EQ(mesh.num_triangles(), 320);
  EXPECT_EQ(mesh.vertices.row(0), Eigen::RowVector3d(0, 0.5, 0));
}

TEST(Ply, ReadsCgalPointCloudWithEmptyFaceElement) {
  const TriangleMesh mesh = parse_file(test::cgal_mesh("b9.ply"));
  EXPECT_EQ(mesh.num_vertices(), 22300);
  EXPECT_EQ(mesh.num_triangles(), 0);
}

TEST(Ply, SkipsUnknownElementsAndPropertiesOfEveryTypeInBinary) {
  std::string bytes =
      "ply\nformat binary_big_endian 1.0\ncomment hand-built\nobj_info nothing\n"
      "element material 2\nproperty list int32 uint8 name\nproperty double shininess\n"
      "element vertex 3\nproperty int16 x\nproperty double y\nproperty float z\n"
      "property ushort confidence\nproperty list uchar float texcoord\nproperty float red\n"
      "property float green\nproperty float blue\n"
      "element face 1\nproperty int flags\nproperty list uint32 uint32 vertex_index\n"
      "property char tag\nend_header\n";
  for (int m = 0; m < 2; ++m) {
    put_big_endian(bytes, std::int32_t{3});
    bytes += "abc";
    put_big_endian(bytes, 0.5);
  }
  for (std::int16_t v = 0; v < 3; ++v) {
    put_big_endian(bytes, v);                                 // x
    put_big_endian(bytes, 2.5 * v);                           // y
    put_big_endian(bytes, -1.0f);                             // z
    put_big_endian(bytes, std::uint16_t{60000});              // confidence
    put_big_endian(bytes, std::uint8_t{2});                   // texcoord length
    put_big_endian(bytes, 0.25f);                             // texcoord
    put_big_endian(bytes, 0.75f);                             // texcoord
    for (int c = 0; c < 3; ++c) put_big_endian(bytes, 0.5f);  // red green blue
  }
  put_big_endian(bytes, std::int32_t{-7});  // flags
  put_big_endian(bytes, std::uint32_t{3});
  for (std::uint32_t i : {2u, 1u, 0u}) put_big_endian(bytes, i);
  put_big_endian(bytes, std::int8_t{-1});  // tag

  const TriangleMesh mesh = parse_ply(bytes, "mixed.ply");
  ASSERT_EQ(mesh.num_vertices(), 3);
  EXPECT_EQ(mesh.vertices.row(2), Eigen::RowVector3d(2, 5, -1));
  ASSERT_EQ(mesh.num_triangles(), 1);
  EXPECT_EQ(mesh.triangles.row(0), Eigen::RowVector3i(2, 1, 0));
  ASSERT_TRUE(mesh.has_vertex_colors());
  EXPECT_EQ(mesh.vertex_colors.row(1), Eigen::RowVector4f(0.5f, 0.5f, 0.5f, 1.0f));
}

TEST(Ply, IgnoresIncompleteColoursAndSplitsPolygonsIntoFans) {
  const TriangleMesh mesh = parse_ply(
      "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
      "property float z\nproperty uchar red\nelement face 1\n"
      "property list uchar int vertex_indices\nend_header\n0 0 0 9\n1 0 0 9\n1 1 0 9\n"
      "0 1 0 9\n4 0 1 2 3\n",
      "quad.ply");
  EXPECT_FALSE(mesh.has_vertex_colors());
  ASSERT_EQ(mesh.num_triangles(), 2);
  EXPECT_EQ(mesh.triangles.row(1), Eigen::RowVector3i(0, 2, 3));
}

TEST(Ply, HostileHeaderIsRejectedBeforeAnythingSizedByItIsAllocated) {
  const auto file = test::test_file("malformed/ply/hostile_count_binary.ply");
  const std::string bytes = test::read_bytes(file);
  ASSERT_LT(bytes.size(), 256u);
  test::largest_allocation = 0;
  EXPECT_TRUE(test::throws_with_message([&] { parse_ply(bytes, file.string()); },
                                        "header declares 2147483647 'vertex' elements"));
  EXPECT_LT(test::largest_allocation.load(), 4096u);

  // Control: the counter does see the parser's allocations for a genuine 1986-vertex file.
  const std::string sphere = format_ply(test::uv_sphere(64, 32));
  test::largest_allocation = 0;
  EXPECT_EQ(parse_ply(sphere, "sphere.ply").num_vertices(), 1986);
  EXPECT_GT(test::largest_allocation.load(), 1986u * 3u * sizeof(double) - 1u);
}

TEST(Ply, RejectsEveryMalformedCorpusFile) {
  const test::MalformedFile cases[] = {
      {"empty.ply", "empty.ply:1: file ends early: expected 'ply'"},
      {"not_ply.ply", "not_ply.ply:1: expected 'ply' (the PLY magic), found 'plx'"},
      {"unknown_format.ply",
       "unknown_format.ply:2: unknown PLY format 'binary_middle_endian'; expected ascii, "
       "binary_little_endian or binary_big_endian"},
      {"missing_format.ply", "missing_format.ply:7: the header has no 'format' line"},
      {"unknown_type.ply", "unknown_type.ply:4: unknown property type 'float16'"},
      {"missing_end_header.ply",
       "missing_end_header.ply:8: file ends early: expected 'end_header'"},
      {"missing_z.ply", "missing_z.ply:3: element 'vertex' has no property 'z'"},
      {"hostile_count_ascii.ply",
       "hostile_count_ascii.ply:9: header declares 2000000000 'vertex' elements but the rest of "
       "the file can hold at most 5"},
      {"hostile_count_binary.ply",
       "hostile_count_binary.ply:9: header declares 2147483647 'vertex' elements but the rest of "
       "the file can hold at most 4"},
      {"truncated_ascii.ply",
       "truncated_ascii.ply:12: file ends early: expected 'x' of element 'vertex'"},
      {"truncated_binary.ply",
       "truncated_binary.ply: byte 218: file ends early: expected 'vertex_indices' of element "
       "'face' (1 bytes, 0 left)"},
      {"binary_list_too_long.ply",
       "binary_list_too_long.ply: byte 205: list of 200 items needs 800 bytes, but only 12 "
       "remain"},
      {"negative_list_length.ply",
       "negative_list_length.ply: byte 204: negative list length -1 for 'vertex_indices' of "
       "element 'face'"},
      {"non_numeric_coordinate.ply",
       "non_numeric_coordinate.ply:11: expected 'y' of element 'vertex' (a finite number), found "
       "'abc'"},
      {"nan_coordinate_ascii.ply",
       "nan_coordinate_ascii.ply:12: expected 'z' of element 'vertex' (a finite number), found "
       "'nan'"},
      {"inf_coordinate_binary.ply",
       "inf_coordinate_binary.ply: byte 178: expected 'x' of element 'vertex' (a finite number), "
       "found inf"},
      {"index_out_of_range.ply",
       "index_out_of_range.ply:15: face 1 uses vertex 7, but the file has 4 vertices"},
      {"two_corner_face.ply",
       "two_corner_face.ply:13: face 0 has 2 corners, but a face needs at least 3"},
      {"colour_out_of_range.ply",
       "colour_out_of_range.ply:11: 'green' of element 'vertex' 256 is outside [0, 255]"},
  };
  test::expect_corpus_rejected("malformed/ply", cases, parse_file);
}

}  // namespace
}  // namespace khz::reduced
