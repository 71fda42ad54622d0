// kilohertz.reduced: triangle and volume meshes, their files, reports and repair.

#include <khz/reduced/io/mesh_file.hpp>
#include <khz/reduced/mesh/mesh_repair.hpp>
#include <khz/reduced/mesh/mesh_report.hpp>
#include <khz/reduced/mesh/triangle_mesh.hpp>
#include <khz/reduced/mesh/volume_mesh.hpp>

#include <pybind11/numpy.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <sstream>
#include <string>

#include "arrays.hpp"
#include "bindings.hpp"

namespace khz::python {

namespace {

using reduced::TriangleMesh;
using reduced::VolumeMesh;

reduced::ColorMatrix colors_from(const py::handle& input) {
  return real_matrix(input, "vertex_colors", -1, 4).cast<float>();
}

TriangleMesh make_triangle_mesh(const py::handle& vertices, const py::handle& triangles,
                                const py::handle& vertex_colors) {
  TriangleMesh mesh;
  mesh.vertices = point_rows(vertices, "vertices").rows();
  mesh.triangles = index_matrix(triangles, "triangles", 3);
  if (!vertex_colors.is_none()) mesh.vertex_colors = colors_from(vertex_colors);
  reduced::validate(mesh);
  return mesh;
}

void bind_triangle_mesh(py::module_& module) {
  py::class_<TriangleMesh>(module, "TriangleMesh", R"(A triangle mesh: positions, triangles and
optional vertex colours (khz::reduced::TriangleMesh).

Triangles are counter-clockwise seen from outside. Nothing is assumed about topology: closed,
open or a polygon soup (analyze_mesh() tells). The array attributes are views of the mesh's own
memory: writing into them changes the mesh; assigning a new array copies and checks it.)")
      .def(py::init(&make_triangle_mesh), py::arg("vertices"), py::arg("triangles"),
           py::arg("vertex_colors") = py::none(),
           R"(Makes a mesh from vertices (V, 3) float (m), triangles (F, 3) int (zero-based
vertex indices) and optional vertex_colors (V, 4) RGBA in [0, 1].
Raises ValueError or TypeError for a wrong shape, dtype or a non-finite value, MeshError for an
index out of range.)")
      .def_property(
          "vertices",
          [](py::object self) { return view_of(self.cast<TriangleMesh&>().vertices, self, true); },
          [](TriangleMesh& mesh, const py::handle& vertices) {
            mesh.vertices = point_rows(vertices, "vertices").rows();
          },
          "(V, 3) float64 vertex positions (m), a view of the mesh's memory.")
      .def_property(
          "triangles",
          [](py::object self) { return view_of(self.cast<TriangleMesh&>().triangles, self, true); },
          [](TriangleMesh& mesh, const py::handle& triangles) {
            mesh.triangles = index_matrix(triangles, "triangles", 3);
          },
          "(F, 3) int32 zero-based vertex indices, a view of the mesh's memory.")
      .def_property(
          "vertex_colors",
          [](py::object self) {
            return view_of(self.cast<TriangleMesh&>().vertex_colors, self, true);
          },
          [](TriangleMesh& mesh, const py::handle& colors) {
            mesh.vertex_colors = colors.is_none() ? reduced::ColorMatrix() : colors_from(colors);
          },
          "(V, 4) float32 RGBA colours in [0, 1], or (0, 4) when the mesh has none.")
      .def_property_readonly("num_vertices", &TriangleMesh::num_vertices)
      .def_property_readonly("num_triangles", &TriangleMesh::num_triangles)
      .def(
          "validate", [](const TriangleMesh& mesh) { reduced::validate(mesh); },
          "Raises MeshError naming the first bad vertex or triangle (non-finite position, index "
          "out of range, colour outside [0, 1]).")
      .def("__repr__",
           [](const TriangleMesh& mesh) {
             return "TriangleMesh(" + std::to_string(mesh.num_vertices()) + " vertices, " +
                    std::to_string(mesh.num_triangles()) + " triangles)";
           })
      .def(py::pickle(
          [](const TriangleMesh& mesh) {
            return py::make_tuple(copy_of(mesh.vertices), copy_of(mesh.triangles),
                                  copy_of(mesh.vertex_colors));
          },
          [](const py::tuple& state) {
            if (state.size() != 3) throw py::value_error("TriangleMesh: bad pickle state");
            py::object colors = state[2];
            if (py::len(colors) == 0) colors = py::none();
            return make_triangle_mesh(state[0], state[1], colors);
          }));
}

VolumeMesh make_volume_mesh(const py::handle& vertices, const py::handle& elements,
                            reduced::ElementType type, const py::handle& groups) {
  VolumeMesh mesh;
  mesh.element_type = type;
  mesh.vertices = point_rows(vertices, "vertices").rows();
  mesh.elements = index_matrix(elements, "elements", nodes_per_element(type));
  if (!groups.is_none() && py::len(groups) > 0) {
    mesh.element_groups =
        index_matrix(py::array::ensure(groups).attr("reshape")(-1, 1), "element_groups", 1);
  }
  reduced::validate(mesh);
  return mesh;
}

void bind_volume_mesh(py::module_& module) {
  py::enum_<reduced::ElementType>(module, "ElementType",
                                  "Element kind of a VolumeMesh; the value is nodes per element.")
      .value("tetrahedron", reduced::ElementType::tetrahedron, "Linear 4-node tetrahedron.")
      .value("hexahedron", reduced::ElementType::hexahedron, "Trilinear 8-node hexahedron.");
  py::class_<VolumeMesh>(module, "VolumeMesh", R"(A volumetric mesh of one element type
(khz::reduced::VolumeMesh): node positions (V, 3) m, elements (E, 4) or (E, 8) node indices in
VTK/Gmsh order, optional element_groups (E,) region ids. Array attributes are views.)")
      .def(py::init(&make_volume_mesh), py::arg("vertices"), py::arg("elements"),
           py::arg("element_type") = reduced::ElementType::tetrahedron,
           py::arg("element_groups") = py::none())
      .def_readonly("element_type", &VolumeMesh::element_type)
      .def_property_readonly(
          "vertices",
          [](py::object self) { return view_of(self.cast<VolumeMesh&>().vertices, self, true); },
          "(V, 3) float64 node positions (m).")
      .def_property_readonly(
          "elements",
          [](py::object self) { return view_of(self.cast<VolumeMesh&>().elements, self, true); },
          "(E, N) int32 node indices, N = 4 or 8.")
      .def_property_readonly(
          "element_groups",
          [](py::object self) {
            return view_of(self.cast<VolumeMesh&>().element_groups, self, true);
          },
          "(E,) int32 region ids, or (0,) when the mesh has none.")
      .def_property_readonly("num_vertices", &VolumeMesh::num_vertices)
      .def_property_readonly("num_elements", &VolumeMesh::num_elements)
      .def("__repr__",
           [](const VolumeMesh& mesh) {
             return "VolumeMesh(" + std::to_string(mesh.num_vertices()) + " nodes, " +
                    std::to_string(mesh.num_elements()) +
                    (mesh.element_type == reduced::ElementType::tetrahedron ? " tetrahedra)"
                                                                            : " hexahedra)");
           })
      .def(py::pickle(
          [](const VolumeMesh& mesh) {
            return py::make_tuple(copy_of(mesh.vertices), copy_of(mesh.elements), mesh.element_type,
                                  copy_of(mesh.element_groups));
          },
          [](const py::tuple& state) {
            if (state.size() != 4) throw py::value_error("VolumeMesh: bad pickle state");
            return make_volume_mesh(state[0], state[1], state[2].cast<reduced::ElementType>(),
                                    state[3]);
          }));
}

void bind_mesh_files(py::module_& module) {
  module.def(
      "read_triangle_mesh",
      [](const std::filesystem::path& file) {
        const py::gil_scoped_release unlocked;
        return reduced::read_triangle_mesh(file);
      },
      py::arg("file"),
      R"(Reads a surface mesh; the extension picks the format: .obj, .off, .stl, .ply.
Raises IoError if it cannot be read, ParseError ("file:line: ...") if it is malformed, Error for
an unknown extension.)");
  module.def(
      "write_triangle_mesh",
      [](const std::filesystem::path& file, const TriangleMesh& mesh, bool binary) {
        const py::gil_scoped_release unlocked;
        reduced::write_triangle_mesh(file, mesh, {.binary = binary});
      },
      py::arg("file"), py::arg("mesh"), py::arg("binary") = true,
      R"(Writes a surface mesh: .obj, .off, .stl, .ply, .vtk or .vtu (binary STL and PLY unless
binary=False). Raises MeshError for an invalid mesh, IoError if the file cannot be written.)");
  module.def(
      "read_volume_mesh",
      [](const std::filesystem::path& file) {
        const py::gil_scoped_release unlocked;
        return reduced::read_volume_mesh(file);
      },
      py::arg("file"),
      "Reads a volume mesh: .msh (Gmsh 2.2 or 4.1) or TetGen .node/.ele. Errors as "
      "read_triangle_mesh().");
  module.def(
      "write_volume_mesh",
      [](const std::filesystem::path& file, const VolumeMesh& mesh) {
        const py::gil_scoped_release unlocked;
        reduced::write_volume_mesh(file, mesh);
      },
      py::arg("file"), py::arg("mesh"),
      "Writes a volume mesh: .msh (2.2), .node (and .ele), .vtk or .vtu.");
}

void bind_report(py::module_& module) {
  using reduced::MeshReport;
  py::class_<MeshReport>(module, "MeshReport",
                         "What analyze_mesh() found (khz::reduced::MeshReport); str() gives the "
                         "summary `khz info` prints.")
      .def_readonly("num_vertices", &MeshReport::num_vertices)
      .def_readonly("num_triangles", &MeshReport::num_triangles)
      .def_property_readonly(
          "bounding_box",
          [](const MeshReport& report) {
            Eigen::Matrix<double, 2, 3, Eigen::RowMajor> corners;
            corners.row(0) = report.bounding_box.min().transpose();
            corners.row(1) = report.bounding_box.max().transpose();
            return copy_of(corners);
          },
          "(2, 3): lowest and highest corner of the referenced vertices (m).")
      .def_readonly("num_edges", &MeshReport::num_edges)
      .def_readonly("num_boundary_edges", &MeshReport::num_boundary_edges,
                    "Edges with exactly one triangle.")
      .def_readonly("num_non_manifold_edges", &MeshReport::num_non_manifold_edges,
                    "Edges with three or more triangles.")
      .def_readonly("num_non_manifold_vertices", &MeshReport::num_non_manifold_vertices)
      .def_readonly("num_unreferenced_vertices", &MeshReport::num_unreferenced_vertices)
      .def_readonly("num_duplicate_vertices", &MeshReport::num_duplicate_vertices)
      .def_readonly("degenerate_triangles", &MeshReport::degenerate_triangles)
      .def_readonly("duplicate_triangles", &MeshReport::duplicate_triangles)
      .def_readonly("num_components", &MeshReport::num_components)
      .def_readonly("edge_manifold", &MeshReport::edge_manifold)
      .def_readonly("vertex_manifold", &MeshReport::vertex_manifold)
      .def_readonly("consistently_oriented", &MeshReport::consistently_oriented)
      .def_readonly("closed", &MeshReport::closed, "Watertight, manifold, no boundary edge.")
      .def_readonly("surface_area", &MeshReport::surface_area, "m².")
      .def_readonly("signed_volume", &MeshReport::signed_volume,
                    "m³, positive for a closed surface with outward normals.")
      .def_readonly("euler_characteristic", &MeshReport::euler_characteristic)
      .def("__str__", [](const MeshReport& report) {
        std::ostringstream text;
        text << report;
        return text.str();
      });
  module.def(
      "analyze_mesh",
      [](const TriangleMesh& mesh) {
        const py::gil_scoped_release unlocked;
        return reduced::analyze_mesh(mesh);
      },
      py::arg("mesh"),
      "Topology and geometry of a mesh: closed, manifold, oriented, components, area, volume. "
      "Raises MeshError for an invalid mesh.");
}

void bind_repair(py::module_& module) {
  py::class_<reduced::HoleFilling>(module, "HoleFilling", "What fill_holes() did.")
      .def_readonly("filled", &reduced::HoleFilling::filled)
      .def_readonly("left_open", &reduced::HoleFilling::left_open);
  py::class_<reduced::RepairSummary>(module, "RepairSummary", "What repair_mesh() changed.")
      .def_readonly("vertices_welded", &reduced::RepairSummary::vertices_welded)
      .def_readonly("triangles_removed", &reduced::RepairSummary::triangles_removed)
      .def_readonly("vertices_split", &reduced::RepairSummary::vertices_split)
      .def_readonly("oriented", &reduced::RepairSummary::oriented)
      .def_readonly("holes", &reduced::RepairSummary::holes);
  module.def(
      "repair_mesh",
      [](TriangleMesh& mesh, double weld_tolerance, bool remove_degenerate, bool orient,
         bool fill_holes) {
        const py::gil_scoped_release unlocked;
        return reduced::repair_mesh(mesh, {.weld_tolerance = weld_tolerance,
                                           .remove_degenerate = remove_degenerate,
                                           .orient = orient,
                                           .fill_holes = fill_holes});
      },
      py::arg("mesh"), py::arg("weld_tolerance") = 0.0, py::arg("remove_degenerate") = true,
      py::arg("orient") = true, py::arg("fill_holes") = false,
      R"(Repairs `mesh` in place, in this order: welds vertices within weld_tolerance (m;
negative skips), removes degenerate and duplicate triangles, orients consistently (outward when
closed), fills holes. Returns a RepairSummary. Raises MeshError for an invalid mesh.)");
}

}  // namespace

void bind_reduced_meshes(py::module_& reduced) {
  bind_triangle_mesh(reduced);
  bind_volume_mesh(reduced);
  bind_mesh_files(reduced);
  bind_report(reduced);
  bind_repair(reduced);
}

}  // namespace khz::python
