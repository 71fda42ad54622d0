#include "product_builders.hpp"

#include <khz/contact/field/mesh_distance_field.hpp>
#include <khz/contact/field/polygon_soup_field.hpp>
#include <khz/reduced/errors.hpp>
#include <khz/reduced/mesh/mesh_report.hpp>

#include <string>

namespace khz::scene::detail {
namespace {

/// A signed field needs a surface that bounds a volume; an open or non-manifold one has no
/// defined inside, and its field comes out inside-out where the pseudonormals guess wrong.
void require_closed_surface(const reduced::TriangleMesh& surface) {
  const reduced::MeshReport report = reduced::analyze_mesh(surface);
  if (report.num_boundary_edges == 0 && report.edge_manifold) return;
  std::string problem =
      report.num_boundary_edges > 0
          ? "is not closed (" + std::to_string(report.num_boundary_edges) + " boundary edges)"
          : "has " + std::to_string(report.num_non_manifold_edges) + " non-manifold edges";
  throw reduced::MeshError(
      "the mesh " + problem +
      ", so its inside is undefined and a signed distance field would be inside-out in places; "
      "set \"fill_holes\": true on the object to close small holes (khz repair --fill-holes "
      "shows the result), or \"soup\": true in its \"field\" to sign the field by an offset "
      "surface");
}

/// The builders' box surrounds the surface with a margin, so a node on its faces that is
/// "inside" means the sign went wrong (self-intersections, inverted triangles).
void require_outside_boundary(const contact::DistanceGrid& field) {
  if (!field.is_signed() || field.boundary_nodes_inside() == 0) return;
  throw reduced::MeshError(
      "the signed distance field is inside-out: " + std::to_string(field.boundary_nodes_inside()) +
      " of the " + std::to_string(field.boundary_node_count()) +
      " nodes on the faces of its box, which surrounds the mesh, are inside; the mesh does not "
      "bound a volume consistently (self-intersections or inverted triangles): set \"soup\": "
      "true in the object's \"field\", or repair the mesh (khz info shows its defects)");
}

}  // namespace

contact::DistanceGrid compute_distance_field(const reduced::TriangleMesh& surface,
                                             const FieldDescription& field,
                                             const reduced::ProgressCallback& progress) {
  contact::DistanceFieldOptions options = field.distance;
  options.progress = progress;
  if (!field.soup) {
    require_closed_surface(surface);
    contact::DistanceGrid grid = contact::signed_distance_field(surface, options);
    require_outside_boundary(grid);
    return grid;
  }
  contact::PolygonSoupFieldOptions soup;
  soup.field = options;
  soup.offset = field.offset;
  contact::DistanceGrid grid = contact::polygon_soup_field(surface, soup).field;
  require_outside_boundary(grid);
  return grid;
}

}  // namespace khz::scene::detail
