#include <khz/reduced/errors.hpp>
#include <khz/reduced/io/off.hpp>
#include <khz/test/fixtures.hpp>
#include <khz/test/generated_meshes.hpp>

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

namespace khz::reduced {
namespace {

TriangleMesh parse_file(const std::filesystem::path& file) {
  return parse_off(test::read_bytes(file), file.string());
}

TriangleMesh round_trip(const TriangleMesh& mesh) { return parse_off(format_off(mesh), "memory"); }

TEST(Off, RoundTripsRandomSoupWithColoursExactly) {
  const TriangleMesh mesh = test::random_soup(200, 7);
  const TriangleMesh parsed = round_trip(mesh);
  EXPECT_EQ(parsed.vertices, mesh.vertices);
  EXPECT_EQ(parsed.triangles, mesh.triangles);
  ASSERT_EQ(parsed.vertex_colors.rows(), mesh.vertex_colors.rows());
  EXPECT_EQ(parsed.vertex_colors, mesh.vertex_colors);
}

TEST(Off, RoundTripsUvSphereExactly) {
  const TriangleMesh mesh = test::uv_sphere(24, 12);
  const TriangleMesh parsed = round_trip(mesh);
  EXPECT_EQ(parsed.vertices, mesh.vertices);
  EXPECT_EQ(parsed.triangles, mesh.triangles);
  EXPECT_FALSE(parsed.has_vertex_colors());
}

TEST(Off, RoundTripsUnitCubeExactly) {
  const TriangleMesh mesh = test::unit_cube_surface();
  const TriangleMesh parsed = round_trip(mesh);
  EXPECT_EQ(parsed.vertices, mesh.vertices);
  EXPECT_EQ(parsed.triangles, mesh.triangles);
}

TEST(Off, WritesCoffWithByteColoursOnlyWhenColoured) {
  EXPECT_TRUE(format_off(test::unit_square()).starts_with("OFF\n4 2 0\n0 0 0\n"));
  TriangleMesh mesh = test::unit_square();
  mesh.vertex_colors.setConstant(4, 4, 1.0f);
  mesh.vertex_colors(0, 0) = 0.5f;
  EXPECT_TRUE(format_off(mesh).starts_with("COFF\n4 2 0\n0 0 0 128 255 255 255\n"));
}

TEST(Off, ReadsCgalDinoWithItsColours) {
  const TriangleMesh mesh = parse_file(test::cgal_mesh("dino.off"));
  EXPECT_EQ(mesh.num_vertices(), 3916);
  EXPECT_EQ(mesh.num_triangles(), 7828);
  ASSERT_TRUE(mesh.has_vertex_colors());
  EXPECT_EQ(mesh.vertex_colors(0, 0), 192.0f / 255.0f);
  EXPECT_EQ(mesh.vertex_colors(3915, 2), 192.0f / 255.0f);
  EXPECT_EQ(mesh.vertex_colors(0, 3), 1.0f);
  EXPECT_EQ(mesh.vertices(0, 0), 0.991441);
  EXPECT_EQ(mesh.vertices(0, 2), -0.555859);
}

TEST(Off, ReadsCgalChineseDragon) {
  const TriangleMesh mesh = parse_file(test::cgal_mesh("ChineseDragon-10kv.off"));
  EXPECT_EQ(mesh.num_vertices(), 10000);
  EXPECT_EQ(mesh.num_triangles(), 19994);
  EXPECT_FALSE(mesh.has_vertex_colors());
}

TEST(Off, ReadsCgalFloatColoursWithCommentsGluedToNumbers) {
  // "1 -1 0 0.9 0 0#red": a fractional component makes the whole colour [0, 1] floats.
  const TriangleMesh mesh = parse_file(test::cgal_mesh("mesh_with_colors.off"));
  EXPECT_EQ(mesh.num_vertices(), 8);
  ASSERT_TRUE(mesh.has_vertex_colors());
  EXPECT_EQ(mesh.vertex_colors(2, 0), 0.9f);
  EXPECT_EQ(mesh.vertex_colors(2, 1), 0.0f);
  EXPECT_EQ(mesh.vertex_colors(1, 2), 0.9f);
}

TEST(Off, SplitsPolygonsIntoFansFromTheFirstCorner) {
  const TriangleMesh mesh =
      parse_off("OFF\n5 1 0\n0 0 0\n1 0 0\n2 1 0\n1 2 0\n0 1 0\n5 0 1 2 3 4\n", "pentagon.off");
  ASSERT_EQ(mesh.num_triangles(), 3);
  EXPECT_EQ(mesh.triangles.row(0), Eigen::RowVector3i(0, 1, 2));
  EXPECT_EQ(mesh.triangles.row(1), Eigen::RowVector3i(0, 2, 3));
  EXPECT_EQ(mesh.triangles.row(2), Eigen::RowVector3i(0, 3, 4));
}

TEST(Off, AcceptsCountsOnTheKeywordLineAndCommentsAnywhere) {
  const TriangleMesh mesh = parse_off(
      "# leading comment\n\nOFF 3 1 0 # counts here\n# between\n0 0 0\n\n1 0 0 # trailing\n"
      "0 1 0\n  # indented comment\n3 0 1 2\n",
      "inline.off");
  EXPECT_EQ(mesh.num_vertices(), 3);
  EXPECT_EQ(mesh.vertices(1, 0), 1.0);
  ASSERT_EQ(mesh.num_triangles(), 1);
  EXPECT_EQ(mesh.triangles.row(0), Eigen::RowVector3i(0, 1, 2));
}

TEST(Off, AcceptsMissingEdgeCount) {
  EXPECT_EQ(parse_off("OFF\n3 1\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", "m.off").num_triangles(), 1);
}

TEST(Off, DecidesColourScalePerVertexLine) {
  const TriangleMesh mesh = parse_off(
      "COFF\n3 1 0\n0 0 0 255 0 51\n1 0 0 0.5 0.25 1 0.75\n0 1 0 1e0 0 0\n3 0 1 2\n", "c.off");
  ASSERT_TRUE(mesh.has_vertex_colors());
  EXPECT_EQ(mesh.vertex_colors.row(0), Eigen::RowVector4f(1.0f, 0.0f, 51.0f / 255.0f, 1.0f));
  EXPECT_EQ(mesh.vertex_colors.row(1), Eigen::RowVector4f(0.5f, 0.25f, 1.0f, 0.75f));
  EXPECT_EQ(mesh.vertex_colors.row(2), Eigen::RowVector4f(1.0f, 0.0f, 0.0f, 1.0f));
}

TEST(Off, ReadsNormalsBeforeColoursInCnoff) {
  const TriangleMesh mesh = parse_off(
      "CNOFF\n3 1 0\n0 0 0 0 0 1 255 0 0\n1 0 0 0 0 1 0 255 0\n0 1 0 0 0 1 0 0 255\n3 0 1 2\n",
      "cn.off");
  EXPECT_EQ(mesh.vertices.row(1), Eigen::RowVector3d(1, 0, 0));
  EXPECT_EQ(mesh.vertex_colors.row(1), Eigen::RowVector4f(0, 1, 0, 1));
  const TriangleMesh normals =
      parse_off("NOFF\n3 1 0\n0 0 0 0 0 1\n1 0 0 0 0 1\n0 1 0 0 0 1\n3 0 1 2\n", "n.off");
  EXPECT_EQ(normals.vertices.row(2), Eigen::RowVector3d(0, 1, 0));
  EXPECT_FALSE(normals.has_vertex_colors());
}

TEST(Off, IgnoresFaceColoursAndTrailingVertexValues) {
  const TriangleMesh mesh =
      parse_off("OFF\n3 1 0\n0 0 0 7 7\n1 0 0\n0 1 0\n3 0 1 2 255 0 0\n", "fc.off");
  EXPECT_EQ(mesh.vertices.row(0), Eigen::RowVector3d(0, 0, 0));
  EXPECT_EQ(mesh.triangles.row(0), Eigen::RowVector3i(0, 1, 2));
  EXPECT_FALSE(mesh.has_vertex_colors());
}

TEST(Off, RejectsAmbiguousColourWithMoreThanFourComponents) {
  EXPECT_TRUE(test::throws_with_message(
      [] { parse_off("COFF\n1 0 0\n0 0 0 1 2 3 4 5\n", "long.off"); },
      "long.off:3: expected a vertex colour of 3 or 4 components after the coordinates, found "
      "more than 4"));
}

TEST(Off, RejectsEveryMalformedCorpusFile) {
  const test::MalformedFile cases[] = {
      {"empty.off", "empty.off:1: file ends early: expected the header keyword OFF"},
      {"wrong_keyword.off",
       "wrong_keyword.off:1: expected the header keyword OFF, COFF, NOFF or CNOFF, found 'OOF'"},
      {"missing_counts.off",
       "missing_counts.off:2: file ends early: expected the vertex and face counts"},
      {"truncated_vertices.off",
       "truncated_vertices.off:9: file ends early: expected vertex 6 of 8"},
      {"truncated_faces.off", "truncated_faces.off:8: file ends early: expected face 2 of 2"},
      {"hostile_vertex_count.off",
       "hostile_vertex_count.off:2: header declares 2000000000 vertices but the rest of the file "
       "can hold at most 5"},
      {"negative_face_count.off", "negative_face_count.off:2: negative faces count -1"},
      {"non_numeric_coordinate.off",
       "non_numeric_coordinate.off:4: expected vertex coordinate (a finite number), found 'abc'"},
      {"non_numeric_index.off",
       "non_numeric_index.off:6: expected vertex index (an integer), found 'x'"},
      {"index_out_of_range.off",
       "index_out_of_range.off:8: face 1 uses vertex 4, but the file has 4 vertices"},
      {"nan_coordinate.off",
       "nan_coordinate.off:4: expected vertex coordinate (a finite number), found 'nan'"},
      {"two_corner_face.off",
       "two_corner_face.off:6: face 0 has 2 corners, but a face needs at least 3"},
      {"missing_colour.off",
       "missing_colour.off:4: expected a vertex colour of 3 or 4 components after the "
       "coordinates, found 0"},
      {"colour_out_of_range.off",
       "colour_out_of_range.off:4: expected a colour component in [0, 255] (or a number in [0, "
       "1]), found '300'"},
  };
  test::expect_corpus_rejected("malformed/off", cases, parse_file);
}

}  // namespace
}  // namespace khz::reduced
