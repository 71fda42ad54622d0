#include <khz/reduced/errors.hpp>
#include <khz/reduced/io/stl.hpp>
#include <khz/test/fixtures.hpp>
#include <khz/test/generated_meshes.hpp>

#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <string>

namespace khz::reduced {
namespace {

TriangleMesh parse_file(const std::filesystem::path& file) {
  return parse_stl(test::read_bytes(file), file.string());
}

VertexMatrix float_rounded(const VertexMatrix& vertices) {
  return vertices.cast<float>().cast<double>();
}

/// STL renumbers vertices in order of first use: compare each triangle corner's position.
void expect_same_corners(const TriangleMesh& parsed, const TriangleMesh& original,
                         const VertexMatrix& expected_positions) {
  ASSERT_EQ(parsed.num_triangles(), original.num_triangles());
  for (Eigen::Index t = 0; t < original.num_triangles(); ++t) {
    for (int k = 0; k < 3; ++k) {
      ASSERT_EQ(parsed.vertices.row(parsed.triangles(t, k)),
                expected_positions.row(original.triangles(t, k)))
          << "triangle " << t << " corner " << k;
    }
  }
}

float float_at(const std::string& bytes, std::size_t offset) {
  float value = 0.0f;
  std::memcpy(&value, bytes.data() + offset, sizeof value);  // the test host is little-endian
  return value;
}

TEST(Stl, BinaryRoundTripOfSoupGivesFloatRoundedCoordinates) {
  const TriangleMesh mesh = test::random_soup(200, 3);
  const std::string bytes = format_stl_binary(mesh);
  EXPECT_EQ(bytes.size(), 84u + 50u * 200u);
  const TriangleMesh parsed = parse_stl(bytes, "soup.stl");
  // No corner is shared, so vertices come back in file order.
  EXPECT_EQ(parsed.vertices, float_rounded(mesh.vertices));
  EXPECT_EQ(parsed.triangles, mesh.triangles);
  EXPECT_FALSE(parsed.has_vertex_colors());
}

TEST(Stl, AsciiRoundTripOfSoupIsExact) {
  const TriangleMesh mesh = test::random_soup(200, 3);
  const TriangleMesh parsed = parse_stl(format_stl_ascii(mesh), "soup.stl");
  EXPECT_EQ(parsed.vertices, mesh.vertices);
  EXPECT_EQ(parsed.triangles, mesh.triangles);
}

TEST(Stl, BinaryRoundTripOfSphereWeldsSharedCorners) {
  const TriangleMesh mesh = test::uv_sphere(24, 12);
  const TriangleMesh parsed = parse_stl(format_stl_binary(mesh), "sphere.stl");
  EXPECT_EQ(parsed.num_vertices(), mesh.num_vertices());
  expect_same_corners(parsed, mesh, float_rounded(mesh.vertices));
}

TEST(Stl, AsciiRoundTripOfSphereWeldsSharedCorners) {
  const TriangleMesh mesh = test::uv_sphere(24, 12);
  const TriangleMesh parsed = parse_stl(format_stl_ascii(mesh), "sphere.stl");
  EXPECT_EQ(parsed.num_vertices(), mesh.num_vertices());
  expect_same_corners(parsed, mesh, mesh.vertices);
}

TEST(Stl, RoundTripsUnitCubeInBothEncodings) {
  const TriangleMesh mesh = test::unit_cube_surface();
  for (const std::string& bytes : {format_stl_binary(mesh), format_stl_ascii(mesh)}) {
    const TriangleMesh parsed = parse_stl(bytes, "cube.stl");
    EXPECT_EQ(parsed.num_vertices(), 8);
    expect_same_corners(parsed, mesh, mesh.vertices);
  }
}

TEST(Stl, BinaryWriterStoresUnitNormalsAndZeroForDegenerateTriangles) {
  TriangleMesh mesh = test::unit_cube_surface();
  mesh.triangles.row(1) << 0, 0, 1;  // degenerate
  const std::string bytes = format_stl_binary(mesh);
  // Triangle 0 = (0, 2, 1) lies in z = 0 and faces outwards, −z.
  EXPECT_EQ(float_at(bytes, 84), 0.0f);
  EXPECT_EQ(float_at(bytes, 88), 0.0f);
  EXPECT_EQ(float_at(bytes, 92), -1.0f);
  for (std::size_t c = 0; c < 3; ++c) EXPECT_EQ(float_at(bytes, 84 + 50 + 4 * c), 0.0f);
}

TEST(Stl, AsciiWriterPrintsFacetNormals) {
  const std::string text = format_stl_ascii(test::unit_square());
  EXPECT_TRUE(
      text.starts_with("solid kilohertz\nfacet normal 0 0 1\n outer loop\n  vertex 0 0 0\n"))
      << text;
}

TEST(Stl, ReadsBinaryWhoseHeaderStartsWithSolid) {
  std::string bytes = format_stl_binary(test::unit_cube_surface());
  bytes.replace(0, 11, "solid cube ");
  const TriangleMesh parsed = parse_stl(bytes, "solid_header.stl");
  EXPECT_EQ(parsed.num_vertices(), 8);
  EXPECT_EQ(parsed.num_triangles(), 12);
}

TEST(Stl, ReadsAsciiKeywordsInAnyCaseAndSeveralSolids) {
  const TriangleMesh mesh = parse_stl(
      "  SOLID first part\nFACET NORMAL 0 0 1\nOUTER LOOP\nVERTEX 0 0 0\nVertex 1 0 0\n"
      "vertex 0 1 0\nENDLOOP\nENDFACET\nENDSOLID first part\n\nsolid second\n"
      "facet normal nan nan nan\nouter loop\nvertex 1 0 0\nvertex 1 1 0\nvertex 0 1 0\nendloop\n"
      "endfacet\nendsolid second\n",
      "two.stl");
  EXPECT_EQ(mesh.num_vertices(), 4);
  ASSERT_EQ(mesh.num_triangles(), 2);
  EXPECT_EQ(mesh.triangles.row(0), Eigen::RowVector3i(0, 1, 2));
  EXPECT_EQ(mesh.triangles.row(1), Eigen::RowVector3i(1, 3, 2));
}

TEST(Stl, MergesOnlyBitIdenticalCorners) {
  // "1.0" and "1" are the same double; "-0" and "0" are not.
  const TriangleMesh mesh = parse_stl(
      "solid s\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\n"
      "endloop\nendfacet\nfacet normal 0 0 1\nouter loop\nvertex -0 0 0\nvertex 1.0 0 0\n"
      "vertex 0 1e0 0\nendloop\nendfacet\nendsolid s\n",
      "weld.stl");
  EXPECT_EQ(mesh.num_vertices(), 4);
  EXPECT_EQ(mesh.triangles.row(1), Eigen::RowVector3i(3, 1, 2));
}

TEST(Stl, ReadsCgalSphereWithSharedVertices) {
  const TriangleMesh mesh = parse_file(test::cgal_mesh("sphere.stl"));
  EXPECT_EQ(mesh.num_vertices(), 162);
  EXPECT_EQ(mesh.num_triangles(), 320);
}

TEST(Stl, ReadsCgalPig) {
  const TriangleMesh mesh = parse_file(test::cgal_mesh("pig.stl"));
  EXPECT_EQ(mesh.num_triangles(), 16848);
  EXPECT_EQ(mesh.num_vertices(), 8642);
}

TEST(Stl, RejectsEveryMalformedCorpusFile) {
  const test::MalformedFile cases[] = {
      {"empty.stl", "empty.stl:1: file ends early: expected 'solid'"},
      {"not_stl.stl", "not_stl.stl:1: expected 'solid', found 'hello'"},
      {"missing_endloop.stl", "missing_endloop.stl:7: expected 'endloop', found 'endfacet'"},
      {"four_corners.stl", "four_corners.stl:7: expected 'endloop', found 'vertex'"},
      {"misspelt_keyword.stl", "misspelt_keyword.stl:3: expected 'loop', found 'lop'"},
      {"truncated_ascii.stl", "truncated_ascii.stl:6: file ends early: expected 'vertex'"},
      {"missing_endsolid.stl",
       "missing_endsolid.stl:9: file ends early: expected 'facet' or 'endsolid'"},
      {"non_numeric_coordinate.stl",
       "non_numeric_coordinate.stl:5: expected vertex coordinate (a finite number), found 'abc'"},
      {"nan_coordinate_ascii.stl",
       "nan_coordinate_ascii.stl:6: expected vertex coordinate (a finite number), found 'nan'"},
      {"nan_coordinate_binary.stl",
       "nan_coordinate_binary.stl: byte 112: expected a finite vertex coordinate, found nan"},
      {"binary_size_mismatch.stl",
       "binary_size_mismatch.stl: byte 80: not ASCII STL (no 'solid' at the start) and not binary "
       "STL: the header declares 3 triangles, so the file should have 234 bytes, but it has 184"},
      {"binary_solid_header_size_mismatch.stl",
       "binary_solid_header_size_mismatch.stl: byte 80: binary STL (its header starts with "
       "'solid', but the file holds non-text bytes) of the wrong size: the header declares 3 "
       "triangles, so the file should have 234 bytes, but it has 184"},
      {"hostile_count.stl",
       "hostile_count.stl: byte 80: not ASCII STL (no 'solid' at the start) and not binary STL: "
       "the header declares 2000000000 triangles, so the file should have 100000000084 bytes, "
       "but it has 134"},
  };
  test::expect_corpus_rejected("malformed/stl", cases, parse_file);
}

}  // namespace
}  // namespace khz::reduced
