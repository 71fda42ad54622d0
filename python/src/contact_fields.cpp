// kilohertz.contact: distance grids, the distance fields of meshes, field files, and point
// queries vectorised over (N, 3) arrays.

#include <khz/contact/field/distance_grid.hpp>
#include <khz/contact/field/grid_geometry.hpp>
#include <khz/contact/field/mesh_distance_field.hpp>
#include <khz/contact/io/distance_field_file.hpp>

#include <pybind11/numpy.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <cstdint>
#include <string>
#include <vector>

#include "arrays.hpp"
#include "bindings.hpp"
#include "progress.hpp"

namespace khz::python {

namespace {

using contact::DistanceGrid;
using contact::GridGeometry;

void bind_grid_geometry(py::module_& module) {
  py::class_<GridGeometry>(module, "GridGeometry", R"(A cube of cells³ cells of edge `spacing` (m)
with its lowest corner at `origin` (m): (cells + 1)³ nodes, node (i, j, k) at
origin + spacing·(i, j, k) (khz::contact::GridGeometry).)")
      .def(py::init([](const py::handle& origin, double spacing, int cells) {
             GridGeometry geometry{vector3_in(origin, "origin"), spacing, cells};
             geometry.validate();
             return geometry;
           }),
           py::arg("origin"), py::arg("spacing"), py::arg("cells"),
           "Raises Error unless spacing > 0 and finite and cells ≥ 1.")
      .def_static(
          "cube_around",
          [](const py::handle& box, double expansion, int cells) {
            const auto corners = real_matrix(box, "box", 2, 3);
            return GridGeometry::cube_around(
                Eigen::AlignedBox3d(corners.row(0).transpose(), corners.row(1).transpose()),
                expansion, cells);
          },
          py::arg("box"), py::arg("expansion") = 1.5, py::arg("cells") = 128,
          R"(The cube centred on box ((2, 3): lowest and highest corner, m) whose edge is
`expansion` times the box's longest side, in `cells` cells per axis (thesis §3.11).)")
      .def_property_readonly("origin", [](const GridGeometry& g) { return vector_out(g.origin); })
      .def_readonly("spacing", &GridGeometry::spacing, "h (m).")
      .def_readonly("cells", &GridGeometry::cells, "Cells per axis.")
      .def_property_readonly("nodes_per_axis", &GridGeometry::nodes_per_axis)
      .def_property_readonly("node_count", &GridGeometry::node_count)
      .def_property_readonly("size", &GridGeometry::size, "Edge of the cube (m).")
      .def("__repr__",
           [](const GridGeometry& g) {
             return "GridGeometry(origin=[" + std::to_string(g.origin.x()) + ", " +
                    std::to_string(g.origin.y()) + ", " + std::to_string(g.origin.z()) +
                    "], spacing=" + std::to_string(g.spacing) +
                    ", cells=" + std::to_string(g.cells) + ")";
           })
      .def(py::pickle(
          [](const GridGeometry& g) {
            return py::make_tuple(g.origin.x(), g.origin.y(), g.origin.z(), g.spacing, g.cells);
          },
          [](const py::tuple& state) {
            if (state.size() != 5) throw py::value_error("GridGeometry: bad pickle state");
            GridGeometry g{
                {state[0].cast<double>(), state[1].cast<double>(), state[2].cast<double>()},
                state[3].cast<double>(),
                state[4].cast<int>()};
            g.validate();
            return g;
          }));
}

/// distance() or distance_and_gradient() at every row of `points`.
py::object query(const DistanceGrid& grid, const py::handle& input, bool with_gradient) {
  const PointRows points = point_rows(input, "points");
  py::array_t<double> values(points.count);
  py::array_t<double> gradients({points.count, Eigen::Index{3}});
  double* value = values.mutable_data();
  double* gradient = gradients.mutable_data();
  {
    const py::gil_scoped_release unlocked;
    const auto rows = points.rows();
    for (Eigen::Index i = 0; i < points.count; ++i) {
      if (with_gradient) {
        Eigen::Vector3d g;
        value[i] = grid.distance_and_gradient(rows.row(i).transpose(), g);
        Eigen::Map<Eigen::Vector3d>(gradient + 3 * i) = g;
      } else {
        value[i] = grid.distance(rows.row(i).transpose());
      }
    }
  }
  if (points.single) {
    if (!with_gradient) return py::float_(value[0]);
    return py::make_tuple(value[0], gradients.attr("reshape")(3));
  }
  if (!with_gradient) return values;
  return py::make_tuple(values, gradients);
}

DistanceGrid make_grid(const GridGeometry& geometry, const py::handle& input, bool is_signed) {
  const auto array = py::array::ensure(input);
  if (!array || array.dtype().kind() != 'f') {
    throw py::type_error("values: expected a float array of the grid's node values");
  }
  const auto floats = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(array);
  const std::int64_t n = geometry.nodes_per_axis();
  if (floats.size() != geometry.node_count() ||
      (floats.ndim() != 1 && !(floats.ndim() == 3 && floats.shape(0) == n && floats.shape(1) == n &&
                               floats.shape(2) == n))) {
    throw py::value_error("values: expected shape (n, n, n) or (n³,) with n = " +
                          std::to_string(n) + " nodes per axis");
  }
  return {geometry, std::vector<float>(floats.data(), floats.data() + floats.size()), is_signed};
}

void bind_distance_grid(py::module_& module) {
  py::class_<DistanceGrid>(module, "DistanceGrid", R"(Distance values (m) at the nodes of a
GridGeometry, signed (negative inside) or unsigned, interpolated trilinearly inside the box and
bounded from below outside it (thesis §3.11, inequality 3.14) (khz::contact::DistanceGrid).)")
      .def(py::init(&make_grid), py::arg("geometry"), py::arg("values"), py::arg("is_signed"),
           R"(values: float array of shape (n, n, n) indexed [k, j, i] (x fastest in memory) or
flat (n³,), n = cells + 1; copied as float32. Raises Error for a non-finite value.)")
      .def_property_readonly("geometry", &DistanceGrid::geometry)
      .def_property_readonly("cell_size", &DistanceGrid::cell_size, "h (m).")
      .def_property_readonly("is_signed", &DistanceGrid::is_signed)
      .def_property_readonly(
          "values",
          [](py::object self) {
            const auto& grid = self.cast<const DistanceGrid&>();
            const auto n = static_cast<py::ssize_t>(grid.geometry().nodes_per_axis());
            const auto item = static_cast<py::ssize_t>(sizeof(float));
            py::array view = py::array_t<float>({n, n, n}, {n * n * item, n * item, item},
                                                grid.values().data(), self);
            view.attr("flags").attr("writeable") = false;
            return view;
          },
          "(n, n, n) float32 node values indexed [k, j, i], a read-only view of the grid.")
      .def_property_readonly("boundary_minimum", &DistanceGrid::boundary_minimum,
                             "A lower bound of the distance on the box's surface (m).")
      .def_property_readonly("boundary_nodes_inside", &DistanceGrid::boundary_nodes_inside,
                             "Nodes on the box's faces with a negative value: any is a sign "
                             "error (an open or self-intersecting mesh).")
      .def(
          "distance",
          [](const DistanceGrid& grid, const py::handle& points) {
            return query(grid, points, false);
          },
          py::arg("points"),
          "The distance (m) at points (N, 3) m: an (N,) array, or a float for one point (3,).")
      .def(
          "distance_and_gradient",
          [](const DistanceGrid& grid, const py::handle& points) {
            return query(grid, points, true);
          },
          py::arg("points"),
          "(distances (N,), gradients (N, 3)) at points (N, 3) m: the gradient of the "
          "interpolant inside the box, the unit vector from the box outside.")
      .def(
          "contains",
          [](const DistanceGrid& grid, const py::handle& input) {
            const PointRows points = point_rows(input, "points");
            py::array_t<bool> inside(points.count);
            for (Eigen::Index i = 0; i < points.count; ++i) {
              inside.mutable_data()[i] = grid.contains(points.rows().row(i).transpose());
            }
            return inside;
          },
          py::arg("points"), "Whether each point (N, 3) lies in the grid's box: (N,) bool.")
      .def("__repr__",
           [](const DistanceGrid& grid) {
             return std::string(grid.is_signed() ? "DistanceGrid(signed, " : "DistanceGrid(") +
                    std::to_string(grid.geometry().cells) +
                    "³ cells, h=" + std::to_string(grid.cell_size()) + " m)";
           })
      .def(py::pickle(
          [](py::object self) {
            const auto& grid = self.cast<const DistanceGrid&>();
            return py::make_tuple(grid.geometry(), self.attr("values").attr("copy")(),
                                  grid.is_signed());
          },
          [](const py::tuple& state) {
            if (state.size() != 3) throw py::value_error("DistanceGrid: bad pickle state");
            return make_grid(state[0].cast<GridGeometry>(), state[1], state[2].cast<bool>());
          }));
}

contact::DistanceFieldOptions field_options(int cells, double box_expansion,
                                            const py::object& geometry, double exact_band,
                                            std::int64_t memory_budget_bytes,
                                            const py::object& progress) {
  contact::DistanceFieldOptions options;
  options.cells = cells;
  options.box_expansion = box_expansion;
  if (!geometry.is_none()) options.geometry = geometry.cast<GridGeometry>();
  options.exact_band = exact_band;
  options.memory_budget_bytes = memory_budget_bytes;
  options.progress = python_progress(progress);
  return options;
}

template <DistanceGrid (*build)(const reduced::TriangleMesh&, const contact::DistanceFieldOptions&)>
DistanceGrid build_field(const reduced::TriangleMesh& mesh, int cells, double box_expansion,
                         const py::object& geometry, double exact_band,
                         std::int64_t memory_budget_bytes, const py::object& progress) {
  const auto options =
      field_options(cells, box_expansion, geometry, exact_band, memory_budget_bytes, progress);
  const py::gil_scoped_release unlocked;
  return build(mesh, options);
}

constexpr const char* field_arguments_doc = R"(
cells: cells per axis of the cube around the mesh (513³ floats take 540 MB at 512);
box_expansion: the cube's edge over the mesh's longest side; geometry: a GridGeometry to use
instead; exact_band: nodes within this many spacings get exact distances (≥ √3);
memory_budget_bytes: larger grids are refused; progress: None or a callable
(stage, done, total) -> bool, False cancels (Cancelled). Ctrl-C stops it (KeyboardInterrupt).
Runs without the GIL, in parallel. Raises MeshError for an invalid mesh, Error for bad options.)";

void bind_field_builders(py::module_& module) {
  const auto add = [&](const char* name, auto builder, const std::string& summary) {
    module.def(name, builder, py::arg("mesh"), py::arg("cells") = 128,
               py::arg("box_expansion") = 1.5, py::arg("geometry") = py::none(),
               py::arg("exact_band") = 3.0, py::arg("memory_budget_bytes") = std::int64_t{1} << 30,
               py::arg("progress") = py::none(), (summary + field_arguments_doc).c_str());
  };
  add("signed_distance_field", &build_field<&contact::signed_distance_field>,
      "The signed distance field (negative inside, m) of a closed, consistently oriented mesh "
      "on a regular grid (thesis §3.11).");
  add("unsigned_distance_field", &build_field<&contact::unsigned_distance_field>,
      "The unsigned distance field (m) of any triangle set: open, non-manifold, a soup.");
  module.def(
      "read_distance_field",
      [](const std::filesystem::path& file) {
        const py::gil_scoped_release unlocked;
        return contact::read_distance_field(file);
      },
      py::arg("file"),
      "Reads a .khzsdf file, bit for bit the grid written. Raises IoError, or ParseError "
      "(\"file: byte N: ...\") for a file that is not one, truncated or corrupted.");
  module.def(
      "write_distance_field",
      [](const std::filesystem::path& file, const DistanceGrid& grid) {
        const py::gil_scoped_release unlocked;
        contact::write_distance_field(file, grid);
      },
      py::arg("file"), py::arg("grid"),
      "Writes a .khzsdf file atomically. Raises IoError if it cannot be written.");
}

}  // namespace

void bind_contact_fields(py::module_& contact) {
  bind_grid_geometry(contact);
  bind_distance_grid(contact);
  bind_field_builders(contact);
}

}  // namespace khz::python
