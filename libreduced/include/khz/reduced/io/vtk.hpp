#pragma once
// Writers for ParaView: legacy VTK (.vtk) and VTK XML unstructured grids (.vtu).

#include <khz/reduced/export.hpp>
#include <khz/reduced/mesh/triangle_mesh.hpp>
#include <khz/reduced/mesh/volume_mesh.hpp>

#include <Eigen/Core>

#include <filesystem>
#include <string>
#include <vector>

namespace khz::reduced {

/// A named array attached to the points or cells of a written mesh.
struct VtkField {
  std::string name;        ///< Array name shown in ParaView (no whitespace).
  Eigen::MatrixXd values;  ///< #points×C or #cells×C; C = 1 (scalar), 3 (vector) or any.
};

/// Arrays written with a mesh: point_data rows match vertices, cell_data rows match
/// triangles or elements. A mismatch is a MeshError naming the field.
struct VtkFields {
  std::vector<VtkField> point_data;
  std::vector<VtkField> cell_data;
};

/// Legacy-VTK ASCII unstructured grid (VTK_TRIANGLE cells).
KHZ_REDUCED_API std::string format_vtk_legacy(const TriangleMesh& mesh,
                                              const VtkFields& fields = {});
/// Legacy-VTK ASCII unstructured grid (VTK_TETRA or VTK_HEXAHEDRON cells); element_groups,
/// when present, are written as the cell array "group".
KHZ_REDUCED_API std::string format_vtk_legacy(const VolumeMesh& mesh, const VtkFields& fields = {});
/// VTK XML UnstructuredGrid (.vtu, ASCII data arrays).
KHZ_REDUCED_API std::string format_vtu(const TriangleMesh& mesh, const VtkFields& fields = {});
/// VTK XML UnstructuredGrid (.vtu, ASCII data arrays); element_groups as cell array "group".
KHZ_REDUCED_API std::string format_vtu(const VolumeMesh& mesh, const VtkFields& fields = {});

}  // namespace khz::reduced
