// ParaView can read what Kilohertz writes, as VTK itself reads it: every kind of file written for
// ParaView (.vtk, .vtu, .vti, .vtp, .pvd) is read back by VTK's own readers (Debian's
// python3-vtk9, through tests/support/vtk_readback.py), and the points, cells, cell types and
// every array's values must be what was written, bit for bit where the format keeps doubles.
#include <khz/contact/field/distance_grid.hpp>
#include <khz/contact/io/distance_field_vti.hpp>
#include <khz/reduced/io/vtk.hpp>
#include <khz/reduced/meshing/box_mesh.hpp>
#include <khz/series/pvd_collection.hpp>
#include <khz/series/vtp_file.hpp>
#include <khz/test/external_program.hpp>
#include <khz/test/fixtures.hpp>
#include <khz/test/generated_meshes.hpp>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

namespace khz {
namespace {

using Json = nlohmann::json;

/// What VTK reads from `file` (vtk_readback.py's JSON); fails the test with VTK's message if it
/// reports an error.
Json read_with_vtk(const std::filesystem::path& file) {
  const std::string python =
      test::required_program(KHZ_VTK_PYTHON, "Python 3 with VTK", "python3-vtk9");
  const test::ProgramRun run = test::run_program(python, {KHZ_VTK_READBACK_SCRIPT, file.string()});
  if (run.exit_code != 0) {
    ADD_FAILURE() << "VTK could not read " << file << ":\n" << run.output;
    return {};
  }
  return Json::parse(run.output);
}

/// A JSON number, or "nan"/"inf"/"-inf" as vtk_readback.py writes the non-finite ones.
double value_of(const Json& j) {
  if (j.is_number()) return j.get<double>();
  const std::string text = j.get<std::string>();
  if (text == "nan") return std::numeric_limits<double>::quiet_NaN();
  return text == "inf" ? std::numeric_limits<double>::infinity()
                       : -std::numeric_limits<double>::infinity();
}

/// Whether VTK's array holds exactly `expected` (row by row, bit for bit; NaN equals NaN).
::testing::AssertionResult holds(const Json& array, const Eigen::MatrixXd& expected) {
  if (array.is_null()) return ::testing::AssertionFailure() << "no such array";
  if (array["components"] != expected.cols()) {
    return ::testing::AssertionFailure() << array["components"] << " components";
  }
  const Json& values = array["values"];
  if (values.size() != static_cast<std::size_t>(expected.size())) {
    return ::testing::AssertionFailure() << values.size() << " values";
  }
  for (Eigen::Index i = 0; i < expected.rows(); ++i) {
    for (Eigen::Index c = 0; c < expected.cols(); ++c) {
      const double read = value_of(values[static_cast<std::size_t>(i * expected.cols() + c)]);
      const double written = expected(i, c);
      if (!(read == written || (std::isnan(read) && std::isnan(written)))) {
        return ::testing::AssertionFailure()
               << "entry (" << i << ", " << c << "): " << read << ", written " << written;
      }
    }
  }
  return ::testing::AssertionSuccess();
}

Eigen::MatrixXd as_matrix(const Eigen::MatrixXi& m) { return m.cast<double>(); }

/// Points, coordinates, cell types and cell connectivity as VTK reads them.
void expect_mesh(const Json& data, const reduced::VertexMatrix& vertices,
                 const Eigen::MatrixXi& cells, int cell_type) {
  ASSERT_EQ(data["points"], vertices.rows());
  ASSERT_EQ(data["cells"], cells.rows());
  Eigen::MatrixXd flat(vertices.rows() * 3, 1);
  for (Eigen::Index v = 0; v < vertices.rows(); ++v)
    flat.middleRows<3>(3 * v) = vertices.row(v).transpose();
  EXPECT_TRUE(holds({{"components", 1}, {"values", data["coordinates"]}}, flat));
  for (Eigen::Index c = 0; c < cells.rows(); ++c) {
    ASSERT_EQ(data["cell_types"][static_cast<std::size_t>(c)], cell_type) << c;
    std::vector<int> expected(static_cast<std::size_t>(cells.cols()));
    for (Eigen::Index k = 0; k < cells.cols(); ++k)
      expected[static_cast<std::size_t>(k)] = cells(c, k);
    EXPECT_EQ(data["cell_points"][static_cast<std::size_t>(c)].get<std::vector<int>>(), expected)
        << c;
  }
}

void write_text(const std::filesystem::path& file, const std::string& text) {
  std::ofstream(file, std::ios::binary) << text;
}

// VTK's cell type codes.
constexpr int vtk_vertex = 1;
constexpr int vtk_triangle = 5;
constexpr int vtk_tetra = 10;
constexpr int vtk_hexahedron = 12;

/// Point data with awkward values: negative, tiny, huge and not short in decimal.
reduced::VtkFields fields_for(Eigen::Index points, Eigen::Index cells) {
  reduced::VtkFields fields;
  Eigen::MatrixXd height(points, 1), velocity(points, 3), pressure(cells, 1);
  for (Eigen::Index p = 0; p < points; ++p) {
    height(p, 0) = 0.1 * static_cast<double>(p) - 1e-300;
    velocity.row(p) << 1.0 / 3.0, -2e100, static_cast<double>(p);
  }
  for (Eigen::Index c = 0; c < cells; ++c) pressure(c, 0) = std::sqrt(static_cast<double>(c) + 2.0);
  fields.point_data = {{"height", height}, {"velocity", velocity}};
  fields.cell_data = {{"pressure", pressure}};
  return fields;
}

TEST(VtkReadback, LegacyAndXmlSurfacesAndVolumesReadAsWritten) {
  const reduced::TriangleMesh surface = test::unit_cube_surface();
  const reduced::VolumeMesh tets = reduced::box_tet_mesh(
      Eigen::Vector3d(-0.1, 0, 0), Eigen::Vector3d(0.2, 0.1, 0.05), {2, 1, 1});
  reduced::VolumeMesh hexes =
      reduced::box_hex_mesh(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(0.3, 0.1, 0.1), {3, 1, 1});
  hexes.element_groups.resize(3);
  hexes.element_groups << 0, 2, 1;
  const reduced::VtkFields surface_fields =
      fields_for(surface.vertices.rows(), surface.triangles.rows());
  const reduced::VtkFields tet_fields = fields_for(tets.vertices.rows(), tets.elements.rows());

  struct Case {
    std::string name, text;
    const reduced::VertexMatrix* vertices;
    Eigen::MatrixXi cells;
    int type;
    const reduced::VtkFields* fields;
  };
  const std::vector<Case> cases{
      {"surface.vtk", reduced::format_vtk_legacy(surface, surface_fields), &surface.vertices,
       surface.triangles, vtk_triangle, &surface_fields},
      {"surface.vtu", reduced::format_vtu(surface, surface_fields), &surface.vertices,
       surface.triangles, vtk_triangle, &surface_fields},
      {"tets.vtk", reduced::format_vtk_legacy(tets, tet_fields), &tets.vertices, tets.elements,
       vtk_tetra, &tet_fields},
      {"tets.vtu", reduced::format_vtu(tets, tet_fields), &tets.vertices, tets.elements, vtk_tetra,
       &tet_fields},
      {"hexes.vtk", reduced::format_vtk_legacy(hexes), &hexes.vertices, hexes.elements,
       vtk_hexahedron, nullptr},
      {"hexes.vtu", reduced::format_vtu(hexes), &hexes.vertices, hexes.elements, vtk_hexahedron,
       nullptr},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    const std::filesystem::path file = test::scratch_file(c.name);
    write_text(file, c.text);
    const Json data = read_with_vtk(file);
    ASSERT_FALSE(data.is_null());
    EXPECT_EQ(data["class"], "vtkUnstructuredGrid");
    expect_mesh(data, *c.vertices, c.cells, c.type);
    if (c.fields != nullptr) {
      for (const reduced::VtkField& field : c.fields->point_data) {
        EXPECT_TRUE(holds(data["point_data"][field.name], field.values)) << field.name;
      }
      for (const reduced::VtkField& field : c.fields->cell_data) {
        EXPECT_TRUE(holds(data["cell_data"][field.name], field.values)) << field.name;
      }
    } else {
      EXPECT_TRUE(holds(data["cell_data"]["group"], as_matrix(hexes.element_groups)));
    }
  }
}

TEST(VtkReadback, DistanceFieldImagesReadAsWrittenInBothEncodings) {
  contact::GridGeometry geometry;
  geometry.origin = Eigen::Vector3d(-0.25, 0.5, 1e-3);
  geometry.spacing = 0.125;
  geometry.cells = 3;
  std::vector<float> values(static_cast<std::size_t>(geometry.node_count()));
  for (std::size_t i = 0; i < values.size(); ++i) {
    values[i] = static_cast<float>(std::sin(0.37 * static_cast<double>(i)) / 3.0);
  }
  values[1] = -0.0f;
  values[2] = std::numeric_limits<float>::denorm_min();
  values[3] = std::numeric_limits<float>::max();
  const contact::DistanceGrid grid(geometry, values, true);
  Eigen::MatrixXd expected(static_cast<Eigen::Index>(values.size()), 1);
  for (std::size_t i = 0; i < values.size(); ++i)
    expected(static_cast<Eigen::Index>(i), 0) = values[i];

  for (const contact::VtiEncoding encoding :
       {contact::VtiEncoding::base64, contact::VtiEncoding::ascii}) {
    SCOPED_TRACE(encoding == contact::VtiEncoding::base64 ? "base64" : "ascii");
    const std::filesystem::path file = test::scratch_file("field.vti");
    contact::write_distance_field_vti(file, grid, encoding);
    const Json data = read_with_vtk(file);
    ASSERT_FALSE(data.is_null());
    EXPECT_EQ(data["class"], "vtkImageData");
    EXPECT_EQ(data["dimensions"], (std::vector<int>{4, 4, 4}));
    EXPECT_EQ(data["origin"], (std::vector<double>{-0.25, 0.5, 1e-3}));
    EXPECT_EQ(data["spacing"], (std::vector<double>{0.125, 0.125, 0.125}));
    EXPECT_EQ(data["point_data"]["signed_distance"]["type"], "float");
    EXPECT_TRUE(holds(data["point_data"]["signed_distance"], expected));
  }
}

TEST(VtkReadback, SeriesSurfacesPointCloudsAndTheirCollectionReadAsWritten) {
  const reduced::TriangleMesh surface = test::unit_cube_surface();
  const Eigen::Index v = surface.vertices.rows();
  Eigen::VectorXd scalar(v);
  Eigen::VectorXi state(v);
  series::ByteVector code(v);
  reduced::VertexMatrix arrow(v, 3);
  for (Eigen::Index p = 0; p < v; ++p) {
    scalar[p] = p == 0 ? std::numeric_limits<double>::quiet_NaN() : 1.0 / static_cast<double>(p);
    state[p] = static_cast<int>(p) - 3;
    code[p] = static_cast<std::uint8_t>(p % 3);
    arrow.row(p) << 0.5 * static_cast<double>(p), -1e-9, std::numeric_limits<double>::infinity();
  }
  const std::vector<series::PointArray> arrays{
      {"scalar", scalar}, {"state", state}, {"code", code}, {"force & <torque>", arrow}};

  const std::filesystem::path directory = test::scratch_directory("series");
  series::PvdCollection collection(directory, "run");
  for (const double time : {0.0, 0.05}) {
    collection.add(time, "surface", [&](const std::filesystem::path& file) {
      series::write_surface_vtp(file, surface.vertices * (1.0 + time), surface.triangles, arrays);
    });
    collection.add(time, "points", [&](const std::filesystem::path& file) {
      series::write_point_cloud_vtp(file, surface.vertices, arrays);
    });
  }
  const Json read = read_with_vtk(collection.file());
  ASSERT_FALSE(read.is_null());
  const Json& datasets = read["datasets"];
  ASSERT_EQ(datasets.size(), 4u);
  for (std::size_t i = 0; i < 4; ++i) {
    SCOPED_TRACE(i);
    const series::PvdEntry& entry = collection.entries()[i];
    const Json& dataset = datasets[i];
    EXPECT_EQ(dataset["timestep"], entry.time);
    EXPECT_EQ(dataset["part"], entry.part);
    EXPECT_EQ(dataset["file"], entry.file.generic_string());
    const Json& data = dataset["data"];
    EXPECT_EQ(data["class"], "vtkPolyData");
    if (entry.part == "surface") {
      expect_mesh(data, surface.vertices * (1.0 + entry.time), surface.triangles, vtk_triangle);
    } else {
      Eigen::MatrixXi vertices(v, 1);
      for (Eigen::Index p = 0; p < v; ++p) vertices(p, 0) = static_cast<int>(p);
      expect_mesh(data, surface.vertices, vertices, vtk_vertex);
    }
    const Json& point_data = data["point_data"];
    EXPECT_EQ(point_data["scalar"]["type"], "double");
    EXPECT_TRUE(holds(point_data["scalar"], scalar));
    EXPECT_EQ(point_data["state"]["type"], "int");
    EXPECT_TRUE(holds(point_data["state"], as_matrix(state)));
    EXPECT_EQ(point_data["code"]["type"], "unsigned char");
    EXPECT_TRUE(holds(point_data["code"], code.cast<double>()));
    EXPECT_TRUE(holds(point_data["force & <torque>"], arrow));
  }
}

}  // namespace
}  // namespace khz
