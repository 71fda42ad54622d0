#include "product_builders.hpp"

#include <khz/contact/field/mesh_distance_field.hpp>
#include <khz/contact/field/polygon_soup_field.hpp>

namespace khz::scene::detail {

contact::DistanceGrid compute_distance_field(const reduced::TriangleMesh& surface,
                                             const FieldDescription& field,
                                             const reduced::ProgressCallback& progress) {
  contact::DistanceFieldOptions options = field.distance;
  options.progress = progress;
  if (!field.soup) return contact::signed_distance_field(surface, options);
  contact::PolygonSoupFieldOptions soup;
  soup.field = options;
  soup.offset = field.offset;
  return contact::polygon_soup_field(surface, soup).field;
}

}  // namespace khz::scene::detail
