#include <khz/reduced/errors.hpp>
#include <khz/reduced/io/vtk.hpp>
#include <khz/test/fixtures.hpp>
#include <khz/test/generated_meshes.hpp>

#include <gtest/gtest.h>

#include <limits>
#include <string>

namespace khz::reduced {
namespace {

/// One tetrahedron in group 4, with a coordinate whose shortest text is not short.
VolumeMesh single_tet() {
  VolumeMesh mesh;
  mesh.vertices.resize(4, 3);
  mesh.vertices << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 0.1;
  mesh.elements.resize(1, 4);
  mesh.elements << 0, 1, 2, 3;
  mesh.element_groups = Eigen::VectorXi::Constant(1, 4);
  return mesh;
}

/// Point fields of width 1, 3 and 2 (SCALARS, VECTORS and FIELD in legacy files).
VtkFields tet_fields() {
  VtkFields fields;
  fields.point_data.push_back({"temperature", Eigen::Vector4d(1.5, 2, 3, 1.0 / 3)});
  Eigen::MatrixXd velocity(4, 3);
  velocity << 1, 0, 0, 0, 1, 0, 0, 0, 1, -1, -1e-20, 1e20;
  fields.point_data.push_back({"velocity", velocity});
  Eigen::MatrixXd pair(4, 2);
  pair << 1, 2, 3, 4, 5, 6, 7, 8;
  fields.point_data.push_back({"pair", pair});
  fields.cell_data.push_back({"volume", Eigen::MatrixXd::Constant(1, 1, 0.25)});
  return fields;
}

TEST(Vtk, LegacyVolumeMeshWithGroupsAndFields) {
  EXPECT_EQ(format_vtk_legacy(single_tet(), tet_fields()),
            "# vtk DataFile Version 3.0\nKilohertz mesh\nASCII\nDATASET UNSTRUCTURED_GRID\n"
            "POINTS 4 double\n0 0 0\n1 0 0\n0 1 0\n0 0 0.1\n"
            "CELLS 1 5\n4 0 1 2 3\nCELL_TYPES 1\n10\n"
            "CELL_DATA 1\nSCALARS group int 1\nLOOKUP_TABLE default\n4\n"
            "SCALARS volume double 1\nLOOKUP_TABLE default\n0.25\n"
            "POINT_DATA 4\nSCALARS temperature double 1\nLOOKUP_TABLE default\n"
            "1.5\n2\n3\n0.3333333333333333\n"
            "VECTORS velocity double\n1 0 0\n0 1 0\n0 0 1\n-1 -1e-20 1e+20\n"
            "FIELD FieldData 1\npair 2 4 double\n1 2\n3 4\n5 6\n7 8\n");
}

TEST(Vtk, LegacyTriangleMeshWithoutFields) {
  TriangleMesh triangle;
  triangle.vertices.resize(3, 3);
  triangle.vertices << 0, 0, 0, 1, 0, 0, 0, 1, 0;
  triangle.triangles.resize(1, 3);
  triangle.triangles << 0, 1, 2;
  EXPECT_EQ(format_vtk_legacy(triangle),
            "# vtk DataFile Version 3.0\nKilohertz mesh\nASCII\nDATASET UNSTRUCTURED_GRID\n"
            "POINTS 3 double\n0 0 0\n1 0 0\n0 1 0\nCELLS 1 4\n3 0 1 2\nCELL_TYPES 1\n5\n");
}

TEST(Vtk, LegacyHexahedraUseCellType12) {
  VolumeMesh cube;
  cube.element_type = ElementType::hexahedron;
  cube.vertices.resize(8, 3);
  cube.vertices << 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0, 0, 1, 1, 0, 1, 1, 1, 1, 0, 1, 1;
  cube.elements.resize(1, 8);
  cube.elements << 0, 1, 2, 3, 4, 5, 6, 7;
  const std::string text = format_vtk_legacy(cube);
  EXPECT_NE(text.find("CELLS 1 9\n8 0 1 2 3 4 5 6 7\nCELL_TYPES 1\n12\n"), std::string::npos);
  EXPECT_NE(
      format_vtu(cube).find("<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n12\n"),
      std::string::npos);
}

TEST(Vtk, VtuVolumeMeshWithGroupsAndFields) {
  VtkFields fields = tet_fields();
  fields.point_data.resize(1);
  EXPECT_EQ(format_vtu(single_tet(), fields),
            "<?xml version=\"1.0\"?>\n"
            "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\">\n"
            "<UnstructuredGrid>\n<Piece NumberOfPoints=\"4\" NumberOfCells=\"1\">\n"
            "<PointData>\n"
            "<DataArray type=\"Float64\" Name=\"temperature\" NumberOfComponents=\"1\" "
            "format=\"ascii\">\n1.5\n2\n3\n0.3333333333333333\n</DataArray>\n"
            "</PointData>\n<CellData>\n"
            "<DataArray type=\"Int32\" Name=\"group\" format=\"ascii\">\n4\n</DataArray>\n"
            "<DataArray type=\"Float64\" Name=\"volume\" NumberOfComponents=\"1\" "
            "format=\"ascii\">\n0.25\n</DataArray>\n"
            "</CellData>\n<Points>\n"
            "<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n"
            "0 0 0\n1 0 0\n0 1 0\n0 0 0.1\n</DataArray>\n</Points>\n<Cells>\n"
            "<DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n0 1 2 3\n"
            "</DataArray>\n"
            "<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n4\n</DataArray>\n"
            "<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n10\n</DataArray>\n"
            "</Cells>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n");
}

TEST(Vtk, VtuTriangleMeshHasTriangleOffsetsAndTypes) {
  const std::string text = format_vtu(test::unit_square());
  EXPECT_NE(text.find("Name=\"offsets\" format=\"ascii\">\n3\n6\n</DataArray>"), std::string::npos);
  EXPECT_NE(text.find("Name=\"types\" format=\"ascii\">\n5\n5\n</DataArray>"), std::string::npos);
  EXPECT_EQ(text.find("<PointData>"), std::string::npos);
  EXPECT_EQ(text.find("<CellData>"), std::string::npos);
}

TEST(Vtk, VtuEscapesXmlCharactersInNames) {
  VtkFields fields;
  fields.point_data.push_back({"a<b>&\"c\"", Eigen::MatrixXd::Zero(4, 1)});
  EXPECT_NE(format_vtu(single_tet(), fields).find("Name=\"a&lt;b&gt;&amp;&quot;c&quot;\""),
            std::string::npos);
}

TEST(Vtk, FieldRowMismatchIsAMeshErrorNamingTheField) {
  VtkFields points;
  points.point_data.push_back({"pressure", Eigen::MatrixXd::Zero(3, 1)});
  EXPECT_TRUE(test::throws_with_message<MeshError>(
      [&] { format_vtk_legacy(single_tet(), points); },
      "point field 'pressure' has 3 rows, but the mesh has 4 vertices"));
  VtkFields cells;
  cells.cell_data.push_back({"damage", Eigen::MatrixXd::Zero(1, 1)});
  EXPECT_TRUE(test::throws_with_message<MeshError>(
      [&] { format_vtu(test::unit_square(), cells); },
      "cell field 'damage' has 1 rows, but the mesh has 2 cells"));
}

TEST(Vtk, FieldNamesMustBeNonEmptyWithoutWhitespace) {
  for (const char* name : {"two words", "tab\tname", "line\n"}) {
    VtkFields fields;
    fields.point_data.push_back({name, Eigen::MatrixXd::Zero(4, 1)});
    EXPECT_TRUE(test::throws_with_message<MeshError>(
        [&] { format_vtk_legacy(single_tet(), fields); },
        "point field '" + std::string(name) + "' has whitespace or control characters"));
  }
  VtkFields unnamed;
  unnamed.cell_data.push_back({"", Eigen::MatrixXd::Zero(1, 1)});
  EXPECT_TRUE(test::throws_with_message<MeshError>([&] { format_vtu(single_tet(), unnamed); },
                                                   "cell field 0 has an empty name"));
}

TEST(Vtk, FieldNamesMustBeUniqueAndAvoidTheGroupArray) {
  VtkFields twice;
  twice.point_data.push_back({"u", Eigen::MatrixXd::Zero(4, 1)});
  twice.point_data.push_back({"u", Eigen::MatrixXd::Zero(4, 3)});
  EXPECT_TRUE(
      test::throws_with_message<MeshError>([&] { format_vtu(single_tet(), twice); },
                                           "point field 'u' has the name of another point field"));
  VtkFields group;
  group.cell_data.push_back({"group", Eigen::MatrixXd::Zero(1, 1)});
  EXPECT_TRUE(
      test::throws_with_message<MeshError>([&] { format_vtk_legacy(single_tet(), group); },
                                           "cell field 'group' clashes with the element groups"));
  VolumeMesh ungrouped = single_tet();
  ungrouped.element_groups.resize(0);
  EXPECT_NO_THROW(format_vtk_legacy(ungrouped, group));
}

TEST(Vtk, FieldsNeedAComponent) {
  VtkFields fields;
  fields.point_data.push_back({"empty", Eigen::MatrixXd::Zero(4, 0)});
  EXPECT_TRUE(test::throws_with_message<MeshError>([&] { format_vtu(single_tet(), fields); },
                                                   "point field 'empty' has no components"));
}

TEST(Vtk, FieldValuesMustBeFinite) {
  VtkFields fields;
  fields.cell_data.push_back({"strain", Eigen::MatrixXd::Zero(1, 2)});
  fields.cell_data[0].values(0, 1) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_TRUE(
      test::throws_with_message<MeshError>([&] { format_vtk_legacy(single_tet(), fields); },
                                           "cell field 'strain' has a non-finite value in row 0"));
}

TEST(Vtk, WritersValidateTheMesh) {
  TriangleMesh square = test::unit_square();
  square.vertices(2, 1) = std::numeric_limits<double>::infinity();
  EXPECT_THROW(format_vtu(square), MeshError);
  VolumeMesh tet = single_tet();
  tet.elements(0, 3) = 4;
  EXPECT_THROW(format_vtk_legacy(tet), MeshError);
}

}  // namespace
}  // namespace khz::reduced
