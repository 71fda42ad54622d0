#pragma once
// Volumetric meshes of linear tetrahedra or trilinear hexahedra, the FEM discretization.

#include <khz/reduced/export.hpp>
#include <khz/reduced/mesh/triangle_mesh.hpp>

#include <Eigen/Core>

namespace khz::reduced {

/// The element kind of a VolumeMesh; the value is the number of nodes per element.
enum class ElementType : int {
  tetrahedron = 4,  ///< Linear 4-node tetrahedron.
  hexahedron = 8,   ///< Trilinear 8-node hexahedron.
};

/// Nodes per element of `type` (4 or 8).
constexpr int nodes_per_element(ElementType type) noexcept { return static_cast<int>(type); }

/// #E×N zero-based node indices, N = nodes_per_element().
using ElementMatrix = Eigen::Matrix<int, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

/// A volumetric mesh with one element type.
///
/// Node order follows VTK and Gmsh. Tetrahedron (0,1,2,3): positive orientation when
/// (x1−x0)·((x2−x0)×(x3−x0)) > 0. Hexahedron: nodes 0–3 the bottom face counter-clockwise seen
/// from the top, nodes 4–7 the top face above them (node 4 above node 0, ...).
struct VolumeMesh {
  ElementType element_type = ElementType::tetrahedron;
  VertexMatrix vertices;           ///< #V×3 node positions.
  ElementMatrix elements;          ///< #E×nodes_per_element(element_type) node indices.
  Eigen::VectorXi element_groups;  ///< Empty, or #E material-group / region ids (>= 0).

  Eigen::Index num_vertices() const noexcept { return vertices.rows(); }
  Eigen::Index num_elements() const noexcept { return elements.rows(); }
};

/// Checks finite coordinates, element width matching the element type, indices in [0, #V),
/// no repeated node within an element, element_groups empty or #E non-negative ids.
/// Orientation and quality are not checked here.
/// @throws MeshError naming the first offending vertex or element.
KHZ_REDUCED_API void validate(const VolumeMesh& mesh);

}  // namespace khz::reduced
