#include <khz/contact/pointshell/repulsion_pointshell.hpp>

#include <cmath>
#include <cstdint>
#include <limits>
#include <string>

namespace khz::contact {

void RepulsionOptions::validate() const {
  const std::string where = "RepulsionOptions: ";
  if (first_level_points < 1) {
    throw Error(where + "first_level_points " + std::to_string(first_level_points) + " is below 1");
  }
  if (levels < 1) throw Error(where + "levels " + std::to_string(levels) + " is below 1");
  // n₀(4ᴸ − 1)/3 points in all, and while the finest level is seeded its four candidates per
  // point beside the coarser levels' points, within int32 indices.
  constexpr double most_points = std::numeric_limits<std::int32_t>::max();
  const double n0 = static_cast<double>(first_level_points);
  const double coarser = n0 * (std::pow(4.0, levels - 1) - 1.0) / 3.0;
  const double finest = n0 * std::pow(4.0, levels - 1);
  if (coarser + 4.0 * finest > most_points) {
    throw Error(where + std::to_string(levels) + " levels from " +
                std::to_string(first_level_points) +
                " points need more than 2^31 - 1 points and seeding candidates");
  }
  if (max_iterations < 1) {
    throw Error(where + "max_iterations " + std::to_string(max_iterations) + " is below 1");
  }
  if (!(tolerance > 0.0 && tolerance < 1.0)) {
    throw Error(where + "tolerance " + std::to_string(tolerance) + " is not in (0, 1)");
  }
  if (!(radius_factor >= 1.0 && radius_factor <= 4.0)) {
    throw Error(where + "radius_factor " + std::to_string(radius_factor) + " is not in [1, 4]");
  }
  if (!(projection_tolerance >= 0.0 && std::isfinite(projection_tolerance))) {
    throw Error(where + "projection_tolerance " + std::to_string(projection_tolerance) +
                " is not finite and ≥ 0");
  }
}

}  // namespace khz::contact
