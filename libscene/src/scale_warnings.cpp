#include "product_builders.hpp"

#include <khz/scene/prepared_scene.hpp>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

namespace khz::scene::detail {
namespace {

/// The longest side of the object's body-frame bounding box as its products give it (m): its
/// pointshell's points, or else its distance field's box shrunk by the box's expansion.
double object_extent(const PreparedObject& object, const ObjectDescription& description) {
  const contact::Pointshell* shell = object.tree != nullptr ? &object.tree->pointshell()
                                     : object.deformable_tree != nullptr
                                         ? &object.deformable_tree->tree().pointshell()
                                         : nullptr;
  if (shell != nullptr && shell->size() > 0) {
    return (shell->points.colwise().maxCoeff() - shell->points.colwise().minCoeff()).maxCoeff();
  }
  const contact::DistanceGrid* field = object.field != nullptr ? object.field.get()
                                       : object.deformed_field != nullptr
                                           ? &object.deformed_field->field(0)
                                           : nullptr;
  if (field == nullptr) return 0.0;
  return field->geometry().size() / description.field.distance.box_expansion;
}

std::string metres(double length) {
  std::ostringstream text;
  text.precision(4);
  text << length << " m";
  return text.str();
}

}  // namespace

std::vector<PrepareWarning> scale_warnings(const PreparedScene& prepared) {
  const std::vector<ObjectDescription>& descriptions = prepared.description.objects;
  std::vector<double> extents;
  for (std::size_t i = 0; i < prepared.objects.size(); ++i) {
    extents.push_back(object_extent(prepared.objects[i], descriptions[i]));
  }
  // The smallest positive size (an object whose points all coincide has none to compare).
  const auto smallest = std::min_element(extents.begin(), extents.end(), [](double a, double b) {
    return a > 0.0 && (!(b > 0.0) || a < b);
  });
  const std::string units_hint =
      "meshes are read in metres: set \"scale\" (e.g. 0.001 for millimetres) or \"size\" (its "
      "longest side in metres)";
  std::vector<PrepareWarning> warnings;
  for (std::size_t i = 0; i < extents.size(); ++i) {
    const double extent = extents[i];
    if (!(extent > 0.0)) continue;
    if (extent > max_plausible_extent || extent < min_plausible_extent) {
      warnings.push_back(
          {descriptions[i].name,
           "it is " + metres(extent) + " across, implausible for a haptic scene; " + units_hint});
    } else if (extent >= max_plausible_ratio * *smallest) {
      const auto other = static_cast<std::size_t>(smallest - extents.begin());
      std::ostringstream ratio;
      ratio.precision(3);
      ratio << extent / *smallest;
      warnings.push_back({descriptions[i].name, "it is " + metres(extent) + " across, " +
                                                    ratio.str() + " times \"" +
                                                    descriptions[other].name + "\" (" +
                                                    metres(*smallest) + "); " + units_hint});
    }
  }
  return warnings;
}

}  // namespace khz::scene::detail
