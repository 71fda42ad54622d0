#include <khz/reduced/errors.hpp>
#include <khz/reduced/mesh/triangle_mesh.hpp>

#include "mesh/mesh_checks.hpp"

#include <string>

namespace khz::reduced {

void validate(const TriangleMesh& mesh) {
  detail::check_finite_vertices(mesh.vertices);
  detail::check_indices(mesh.triangles, mesh.num_vertices(), "triangle");
  if (mesh.vertex_colors.rows() == 0) return;
  if (mesh.vertex_colors.rows() != mesh.num_vertices()) {
    throw MeshError("mesh has " + std::to_string(mesh.vertex_colors.rows()) +
                    " vertex colours for " + std::to_string(mesh.num_vertices()) + " vertices");
  }
  for (Eigen::Index v = 0; v < mesh.vertex_colors.rows(); ++v) {
    const auto color = mesh.vertex_colors.row(v);
    if (!(color.minCoeff() >= 0.0f && color.maxCoeff() <= 1.0f)) {
      throw MeshError("vertex " + std::to_string(v) + " has a colour channel outside [0, 1]", v);
    }
  }
}

}  // namespace khz::reduced
