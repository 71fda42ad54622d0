#include <khz/scene/prepared_scene.hpp>

#include <algorithm>

namespace khz::scene {

std::string_view step_name(PrepareStep step) noexcept {
  switch (step) {
    case PrepareStep::volume_mesh:
      return "volume_mesh";
    case PrepareStep::reduced_model:
      return "reduced_model";
    case PrepareStep::distance_field:
      return "distance_field";
    case PrepareStep::pointshell:
      return "pointshell";
    case PrepareStep::point_tree:
      return "point_tree";
    case PrepareStep::deformed_field:
      return "deformed_field";
    case PrepareStep::mass_properties:
      return "mass_properties";
  }
  return "?";
}

std::string_view origin_name(PrepareRecord::Origin origin) noexcept {
  switch (origin) {
    case PrepareRecord::Origin::computed:
      return "computed";
    case PrepareRecord::Origin::read:
      return "read";
    case PrepareRecord::Origin::built:
      return "built";
  }
  return "?";
}

int PreparedScene::count(PrepareRecord::Origin origin) const noexcept {
  return static_cast<int>(std::count_if(
      records.begin(), records.end(), [&](const PrepareRecord& r) { return r.origin == origin; }));
}

double PreparedScene::total_seconds() const noexcept {
  double total = 0.0;
  for (const PrepareRecord& record : records) total += record.seconds;
  return total;
}

}  // namespace khz::scene
