#include "product_builders.hpp"

#include <khz/reduced/errors.hpp>
#include <khz/reduced/mesh/mesh_report.hpp>

#include <string>

namespace khz::scene::detail {

void require_closed_surface(const reduced::TriangleMesh& surface, std::string_view needed_by,
                            std::string_view remedy) {
  const reduced::MeshReport report = reduced::analyze_mesh(surface);
  std::string problem;
  if (report.num_boundary_edges > 0) {
    problem = "is not closed (" + std::to_string(report.num_boundary_edges) + " boundary edges)";
  } else if (!report.edge_manifold) {
    problem = "has " + std::to_string(report.num_non_manifold_edges) + " non-manifold edges";
  } else if (!report.consistently_oriented) {
    problem = "is not consistently oriented";
  } else {
    return;
  }
  throw reduced::MeshError("the mesh " + problem + ", so its inside is undefined and " +
                           std::string(needed_by) + "; " + std::string(remedy) +
                           " (khz info shows the mesh's defects, khz repair --fill-holes closes "
                           "holes and orients)");
}

}  // namespace khz::scene::detail
