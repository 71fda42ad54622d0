#include <khz/reduced/errors.hpp>
#include <khz/reduced/io/vtk.hpp>

#include "detail/xml_text.hpp"
#include "io/volume_parsing.hpp"

#include <algorithm>
#include <cstdint>
#include <span>
#include <string>
#include <type_traits>
#include <vector>

namespace khz::reduced {
namespace {

// VTK cell type ids (vtkCellType.h). Our hexahedron node order is VTK's.
constexpr int vtk_triangle = 5;
constexpr int vtk_tetra = 10;
constexpr int vtk_hexahedron = 12;

/// Either mesh kind as VTK sees it: points, same-width cells and optional cell groups.
struct Grid {
  const VertexMatrix& points;
  Eigen::Ref<const ElementMatrix> cells;
  int cell_type;
  std::span<const int> groups;  // empty, or one per cell

  Eigen::Index num_points() const { return points.rows(); }
  Eigen::Index num_cells() const { return cells.rows(); }
};

// Both grid_of() validate the mesh: VTK cannot read non-finite coordinates or bad indices, and
// the writers index element_groups by element.

Grid grid_of(const TriangleMesh& mesh) {
  validate(mesh);
  return {mesh.vertices, mesh.triangles, vtk_triangle, {}};
}

Grid grid_of(const VolumeMesh& mesh) {
  validate(mesh);
  const int type = mesh.element_type == ElementType::tetrahedron ? vtk_tetra : vtk_hexahedron;
  return {mesh.vertices,
          mesh.elements,
          type,
          {mesh.element_groups.data(), static_cast<std::size_t>(mesh.element_groups.size())}};
}

const char* const group_name = "group";

/// Rejects fields VTK cannot read back: bad names, wrong row counts, no components, non-finite
/// values (the legacy reader stops at "nan").
void check_fields(const std::vector<VtkField>& fields, Eigen::Index rows, const std::string& kind,
                  const char* row_noun, bool has_groups) {
  for (std::size_t i = 0; i < fields.size(); ++i) {
    const VtkField& field = fields[i];
    const std::string name = kind + " field '" + field.name + "'";
    if (field.name.empty()) {
      throw MeshError(kind + " field " + std::to_string(i) + " has an empty name");
    }
    // Both formats separate names from what follows by whitespace.
    if (std::any_of(field.name.begin(), field.name.end(),
                    [](unsigned char c) { return c <= ' ' || c == 0x7f; })) {
      throw MeshError(name + " has whitespace or control characters in its name");
    }
    if (field.values.rows() != rows) {
      throw MeshError(name + " has " + std::to_string(field.values.rows()) +
                      " rows, but the mesh has " + std::to_string(rows) + " " + row_noun);
    }
    if (field.values.cols() == 0) throw MeshError(name + " has no components");
    for (Eigen::Index r = 0; r < rows; ++r) {
      if (!field.values.row(r).allFinite()) {
        throw MeshError(name + " has a non-finite value in row " + std::to_string(r));
      }
    }
    if (has_groups && field.name == group_name) {
      throw MeshError(name + " clashes with the element groups, written as cell array 'group'");
    }
    const auto same_name = [&](const VtkField& other) { return other.name == field.name; };
    if (std::any_of(fields.begin(), fields.begin() + static_cast<std::ptrdiff_t>(i), same_name)) {
      throw MeshError(name + " has the name of another " + kind + " field");
    }
  }
}

void check_fields(const Grid& grid, const VtkFields& fields) {
  check_fields(fields.point_data, grid.num_points(), "point", "vertices", false);
  check_fields(fields.cell_data, grid.num_cells(), "cell", "cells", !grid.groups.empty());
}

/// Appends row `r` of `values` as one space-separated line.
template <typename Derived>
void append_row(std::string& out, const Eigen::DenseBase<Derived>& values, Eigen::Index r) {
  for (Eigen::Index c = 0; c < values.cols(); ++c) {
    if (c > 0) out += ' ';
    if constexpr (std::is_floating_point_v<typename Derived::Scalar>) {
      detail::append_number(out, values(r, c));
    } else {
      detail::append_number<std::int64_t>(out, values(r, c));
    }
  }
  out += '\n';
}

template <typename Derived>
void append_rows(std::string& out, const Eigen::DenseBase<Derived>& values) {
  for (Eigen::Index r = 0; r < values.rows(); ++r) append_row(out, values, r);
}

void append_groups(std::string& out, std::span<const int> groups) {
  for (const int group : groups) {
    detail::append_number<std::int64_t>(out, group);
    out += '\n';
  }
}

// ---- Legacy VTK ----

/// Width 1 as SCALARS, width 3 as VECTORS, other widths together in one FIELD block.
void append_legacy_arrays(std::string& out, const std::vector<VtkField>& fields) {
  std::vector<const VtkField*> others;
  for (const VtkField& field : fields) {
    if (field.values.cols() == 1) {
      out += "SCALARS " + field.name + " double 1\nLOOKUP_TABLE default\n";
    } else if (field.values.cols() == 3) {
      out += "VECTORS " + field.name + " double\n";
    } else {
      others.push_back(&field);
      continue;
    }
    append_rows(out, field.values);
  }
  if (others.empty()) return;
  out += "FIELD FieldData " + std::to_string(others.size()) + '\n';
  for (const VtkField* field : others) {
    out += field->name + ' ' + std::to_string(field->values.cols()) + ' ' +
           std::to_string(field->values.rows()) + " double\n";
    append_rows(out, field->values);
  }
}

std::string legacy(const Grid& grid, const VtkFields& fields) {
  check_fields(grid, fields);
  const Eigen::Index width = grid.cells.cols();
  std::string out =
      "# vtk DataFile Version 3.0\nKilohertz mesh\nASCII\nDATASET UNSTRUCTURED_GRID\n";
  out += "POINTS " + std::to_string(grid.num_points()) + " double\n";
  append_rows(out, grid.points);

  out += "CELLS " + std::to_string(grid.num_cells()) + ' ' +
         std::to_string(grid.num_cells() * (width + 1)) + '\n';
  const std::string prefix = std::to_string(width) + ' ';
  for (Eigen::Index c = 0; c < grid.num_cells(); ++c) {
    out += prefix;
    append_row(out, grid.cells, c);
  }
  out += "CELL_TYPES " + std::to_string(grid.num_cells()) + '\n';
  const std::string type_line = std::to_string(grid.cell_type) + '\n';
  for (Eigen::Index c = 0; c < grid.num_cells(); ++c) out += type_line;

  if (!grid.groups.empty() || !fields.cell_data.empty()) {
    out += "CELL_DATA " + std::to_string(grid.num_cells()) + '\n';
    if (!grid.groups.empty()) {
      out += std::string("SCALARS ") + group_name + " int 1\nLOOKUP_TABLE default\n";
      append_groups(out, grid.groups);
    }
    append_legacy_arrays(out, fields.cell_data);
  }
  if (!fields.point_data.empty()) {
    out += "POINT_DATA " + std::to_string(grid.num_points()) + '\n';
    append_legacy_arrays(out, fields.point_data);
  }
  return out;
}

// ---- VTK XML (.vtu) ----

/// Opens a DataArray element; `name` and `components` are omitted when empty or zero.
void open_data_array(std::string& out, const char* type, const std::string& name,
                     Eigen::Index components) {
  out += "<DataArray type=\"";
  out += type;
  out += '"';
  if (!name.empty()) out += " Name=\"" + detail::xml_escaped(name) + '"';
  if (components > 0) out += " NumberOfComponents=\"" + std::to_string(components) + '"';
  out += " format=\"ascii\">\n";
}

void append_vtu_arrays(std::string& out, const std::vector<VtkField>& fields) {
  for (const VtkField& field : fields) {
    open_data_array(out, "Float64", field.name, field.values.cols());
    append_rows(out, field.values);
    out += "</DataArray>\n";
  }
}

std::string vtu(const Grid& grid, const VtkFields& fields) {
  check_fields(grid, fields);
  std::string out =
      "<?xml version=\"1.0\"?>\n"
      "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\">\n"
      "<UnstructuredGrid>\n";
  out += "<Piece NumberOfPoints=\"" + std::to_string(grid.num_points()) + "\" NumberOfCells=\"" +
         std::to_string(grid.num_cells()) + "\">\n";
  if (!fields.point_data.empty()) {
    out += "<PointData>\n";
    append_vtu_arrays(out, fields.point_data);
    out += "</PointData>\n";
  }
  if (!grid.groups.empty() || !fields.cell_data.empty()) {
    out += "<CellData>\n";
    if (!grid.groups.empty()) {
      open_data_array(out, "Int32", group_name, 0);
      append_groups(out, grid.groups);
      out += "</DataArray>\n";
    }
    append_vtu_arrays(out, fields.cell_data);
    out += "</CellData>\n";
  }
  out += "<Points>\n";
  open_data_array(out, "Float64", "", 3);
  append_rows(out, grid.points);
  out += "</DataArray>\n</Points>\n<Cells>\n";
  // Int64 so offsets stay exact past 2^31 connectivity entries.
  open_data_array(out, "Int64", "connectivity", 0);
  append_rows(out, grid.cells);
  out += "</DataArray>\n";
  open_data_array(out, "Int64", "offsets", 0);
  const Eigen::Index width = grid.cells.cols();
  for (Eigen::Index c = 1; c <= grid.num_cells(); ++c) {
    detail::append_number<std::int64_t>(out, c * width);
    out += '\n';
  }
  out += "</DataArray>\n";
  open_data_array(out, "UInt8", "types", 0);
  const std::string type_line = std::to_string(grid.cell_type) + '\n';
  for (Eigen::Index c = 0; c < grid.num_cells(); ++c) out += type_line;
  out += "</DataArray>\n</Cells>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n";
  return out;
}

}  // namespace

std::string format_vtk_legacy(const TriangleMesh& mesh, const VtkFields& fields) {
  return legacy(grid_of(mesh), fields);
}

std::string format_vtk_legacy(const VolumeMesh& mesh, const VtkFields& fields) {
  return legacy(grid_of(mesh), fields);
}

std::string format_vtu(const TriangleMesh& mesh, const VtkFields& fields) {
  return vtu(grid_of(mesh), fields);
}

std::string format_vtu(const VolumeMesh& mesh, const VtkFields& fields) {
  return vtu(grid_of(mesh), fields);
}

}  // namespace khz::reduced
