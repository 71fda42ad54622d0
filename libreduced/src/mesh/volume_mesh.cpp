#include <khz/reduced/errors.hpp>
#include <khz/reduced/mesh/volume_mesh.hpp>

#include "mesh/mesh_checks.hpp"

#include <string>

namespace khz::reduced {

void validate(const VolumeMesh& mesh) {
  const int width = nodes_per_element(mesh.element_type);
  if (mesh.elements.rows() > 0 && mesh.elements.cols() != width) {
    throw MeshError("elements have " + std::to_string(mesh.elements.cols()) +
                    " nodes, the element type needs " + std::to_string(width));
  }
  detail::check_finite_vertices(mesh.vertices);
  detail::check_indices(mesh.elements, mesh.num_vertices(), "element");
  for (Eigen::Index e = 0; e < mesh.num_elements(); ++e) {
    for (int a = 0; a < width; ++a) {
      for (int b = a + 1; b < width; ++b) {
        if (mesh.elements(e, a) == mesh.elements(e, b)) {
          throw MeshError("element " + std::to_string(e) + " uses vertex " +
                              std::to_string(mesh.elements(e, a)) + " twice",
                          e);
        }
      }
    }
  }
  if (mesh.element_groups.size() == 0) return;
  if (mesh.element_groups.size() != mesh.num_elements()) {
    throw MeshError("mesh has " + std::to_string(mesh.element_groups.size()) +
                    " element groups for " + std::to_string(mesh.num_elements()) + " elements");
  }
  for (Eigen::Index e = 0; e < mesh.element_groups.size(); ++e) {
    if (mesh.element_groups[e] < 0) {
      throw MeshError("element " + std::to_string(e) + " has negative group " +
                          std::to_string(mesh.element_groups[e]),
                      e);
    }
  }
}

}  // namespace khz::reduced
