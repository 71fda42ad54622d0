#include "product_builders.hpp"

#include <khz/contact/field/mesh_distance_field.hpp>
#include <khz/contact/field/polygon_soup_field.hpp>
#include <khz/reduced/errors.hpp>

#include <string>

namespace khz::scene::detail {
namespace {

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
    require_closed_surface(surface, "a signed distance field would be inside-out in places",
                           "set \"fill_holes\": true on the object to close small holes, or "
                           "\"soup\": true in its \"field\" to sign the field by an offset "
                           "surface");
  }
  contact::PolygonSoupFieldOptions soup;
  soup.field = options;
  soup.offset = field.offset;
  contact::DistanceGrid grid = field.soup ? contact::polygon_soup_field(surface, soup).field
                                          : contact::signed_distance_field(surface, options);
  require_outside_boundary(grid);
  return grid;
}

}  // namespace khz::scene::detail
