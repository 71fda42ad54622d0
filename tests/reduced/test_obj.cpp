#include <khz/reduced/errors.hpp>
#include <khz/reduced/io/obj.hpp>
#include <khz/test/fixtures.hpp>
#include <khz/test/generated_meshes.hpp>

#include <gtest/gtest.h>

#include <bit>
#include <cstdint>
#include <filesystem>
#include <string>

namespace khz::reduced {
namespace {

TriangleMesh parse_file(const std::filesystem::path& file) {
  return parse_obj(test::read_bytes(file), file.string());
}

TriangleMesh round_trip(const TriangleMesh& mesh) { return parse_obj(format_obj(mesh), "memory"); }

TEST(Obj, RoundTripsRandomSoupWithRgbColoursExactly) {
  const TriangleMesh mesh = test::random_soup(200, 11);
  const TriangleMesh parsed = round_trip(mesh);
  EXPECT_EQ(parsed.vertices, mesh.vertices);
  EXPECT_EQ(parsed.triangles, mesh.triangles);
  ASSERT_EQ(parsed.vertex_colors.rows(), mesh.vertex_colors.rows());
  // OBJ's colour extension has no alpha: RGB come back bit-exact, alpha is opaque.
  EXPECT_EQ(parsed.vertex_colors.leftCols(3), mesh.vertex_colors.leftCols(3));
  EXPECT_TRUE((parsed.vertex_colors.col(3).array() == 1.0f).all());
}

TEST(Obj, ReadsColourChannelsAsFloatsRoundedOnce) {
  // The one float in [0, 1] whose shortest text, read as a double and then narrowed, would
  // land on a neighbouring float.
  const float channel = std::bit_cast<float>(std::uint32_t{0x15ae43fd});
  TriangleMesh mesh = test::unit_square();
  mesh.vertex_colors.setConstant(4, 4, 1.0f);
  mesh.vertex_colors(2, 1) = channel;
  const std::string text = format_obj(mesh);
  ASSERT_NE(text.find("v 1 1 0 1 7.038531e-26 1\n"), std::string::npos) << text;
  EXPECT_EQ(parse_obj(text, "tiny.obj").vertex_colors(2, 1), channel);
}

TEST(Obj, RoundTripsUvSphereExactly) {
  const TriangleMesh mesh = test::uv_sphere(24, 12);
  const TriangleMesh parsed = round_trip(mesh);
  EXPECT_EQ(parsed.vertices, mesh.vertices);
  EXPECT_EQ(parsed.triangles, mesh.triangles);
  EXPECT_FALSE(parsed.has_vertex_colors());
}

TEST(Obj, RoundTripsUnitCubeExactly) {
  const TriangleMesh mesh = test::unit_cube_surface();
  const TriangleMesh parsed = round_trip(mesh);
  EXPECT_EQ(parsed.vertices, mesh.vertices);
  EXPECT_EQ(parsed.triangles, mesh.triangles);
}

TEST(Obj, WritesOneBasedFacesAndShortestNumbers) {
  EXPECT_EQ(format_obj(test::unit_square()),
            "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3\nf 1 3 4\n");
}

TEST(Obj, ReadsEveryCornerForm) {
  const TriangleMesh mesh = parse_obj(
      "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\nf 1 2 3\nf 1/1 2/1 3/1\nf 1//1 2//1 3//1\n"
      "f 1/1/1 2/1/1 3/1/1\n",
      "forms.obj");
  ASSERT_EQ(mesh.num_triangles(), 4);
  for (Eigen::Index t = 0; t < 4; ++t) {
    EXPECT_EQ(mesh.triangles.row(t), Eigen::RowVector3i(0, 1, 2));
  }
}

TEST(Obj, ResolvesNegativeIndicesAgainstVerticesDefinedSoFar) {
  const TriangleMesh mesh =
      parse_obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nf -3 -2 -1\nv 1 1 0\nf -3 -1 -2\n", "neg.obj");
  ASSERT_EQ(mesh.num_triangles(), 2);
  EXPECT_EQ(mesh.triangles.row(0), Eigen::RowVector3i(0, 1, 2));
  EXPECT_EQ(mesh.triangles.row(1), Eigen::RowVector3i(1, 3, 2));
}

TEST(Obj, SplitsPolygonsIntoFansFromTheFirstCorner) {
  const TriangleMesh mesh =
      parse_obj("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n", "quad.obj");
  ASSERT_EQ(mesh.num_triangles(), 2);
  EXPECT_EQ(mesh.triangles.row(0), Eigen::RowVector3i(0, 1, 2));
  EXPECT_EQ(mesh.triangles.row(1), Eigen::RowVector3i(0, 2, 3));
}

TEST(Obj, IgnoresWAndStatementsWithoutSurfaceData) {
  const TriangleMesh mesh = parse_obj(
      "mtllib a.mtl\no thing\ng group\nv 0 0 0 1\nv 1 0 0 0.5\nv 0 1 0\nusemtl red\ns off\n"
      "l 1 2\np 3\nf 1 2 3 # the only face\n",
      "misc.obj");
  EXPECT_EQ(mesh.num_vertices(), 3);
  EXPECT_EQ(mesh.vertices.row(1), Eigen::RowVector3d(1, 0, 0));
  EXPECT_EQ(mesh.num_triangles(), 1);
  EXPECT_FALSE(mesh.has_vertex_colors());
}

TEST(Obj, GivesUncolouredVerticesWhiteWhenOthersHaveColours) {
  const TriangleMesh mesh =
      parse_obj("v 0 0 0\nv 1 0 0 0.25 0.5 0.75\nv 0 1 0\nf 1 2 3\n", "partial.obj");
  ASSERT_TRUE(mesh.has_vertex_colors());
  EXPECT_EQ(mesh.vertex_colors.row(0), Eigen::RowVector4f(1, 1, 1, 1));
  EXPECT_EQ(mesh.vertex_colors.row(1), Eigen::RowVector4f(0.25f, 0.5f, 0.75f, 1.0f));
  EXPECT_EQ(mesh.vertex_colors.row(2), Eigen::RowVector4f(1, 1, 1, 1));
}

TEST(Obj, AcceptsCommentsGluedToNumbers) {
  const TriangleMesh mesh = parse_obj("v 0 0 0\nv 1 0 0#x\nv 0 1 0\nf 1 2 3#face\n", "c.obj");
  EXPECT_EQ(mesh.vertices.row(1), Eigen::RowVector3d(1, 0, 0));
  EXPECT_EQ(mesh.num_triangles(), 1);
}

TEST(Obj, RejectsEveryMalformedCorpusFile) {
  const test::MalformedFile cases[] = {
      {"empty.obj", "empty.obj:1: file ends early: expected at least one vertex ('v' line)"},
      {"no_vertices.obj",
       "no_vertices.obj:3: file ends early: expected at least one vertex ('v' line)"},
      {"index_zero.obj",
       "index_zero.obj:4: face 0 uses vertex index 0, but OBJ indices start at 1 (or count back "
       "from -1)"},
      {"two_corner_face.obj",
       "two_corner_face.obj:4: face 0 has 2 corners, but a face needs at least 3"},
      {"index_out_of_range.obj",
       "index_out_of_range.obj:6: face 1 uses vertex 5, but only 4 vertices are defined before "
       "it"},
      {"negative_index_out_of_range.obj",
       "negative_index_out_of_range.obj:4: face 0 uses vertex -4, but only 3 vertices are "
       "defined before it"},
      {"non_numeric_coordinate.obj",
       "non_numeric_coordinate.obj:2: expected vertex coordinate (a finite number), found 'abc'"},
      {"non_numeric_index.obj",
       "non_numeric_index.obj:4: expected a vertex index (an integer, optionally with "
       "/texture/normal indices), found 'x/2'"},
      {"inf_coordinate.obj",
       "inf_coordinate.obj:2: expected vertex coordinate (a finite number), found 'inf'"},
      {"five_number_vertex.obj",
       "five_number_vertex.obj:2: expected 'v x y z', 'v x y z w' or 'v x y z r g b', found 5 "
       "values"},
      {"colour_out_of_range.obj",
       "colour_out_of_range.obj:2: expected a vertex colour component in [0, 1], found '1.5'"},
      {"truncated_vertex.obj",
       "truncated_vertex.obj:3: expected 'v x y z', 'v x y z w' or 'v x y z r g b', found 2 "
       "values"},
  };
  test::expect_corpus_rejected("malformed/obj", cases, parse_file);
}

}  // namespace
}  // namespace khz::reduced
