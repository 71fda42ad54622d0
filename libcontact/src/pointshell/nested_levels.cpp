#include <khz/contact/pointshell/farthest_point_order.hpp>
#include <khz/contact/pointshell/nested_levels.hpp>

#include "pointshell/split_mix.hpp"

#include <limits>
#include <string>

namespace khz::contact {

std::vector<Eigen::Index> level_ends(Eigen::Index count, const LevelSchedule& schedule) {
  if (count < 1) throw Error("level_ends: no points");
  if (schedule.first_level_size < 1) {
    throw Error("LevelSchedule: first_level_size " + std::to_string(schedule.first_level_size) +
                " is below 1");
  }
  if (schedule.growth < 2) {
    throw Error("LevelSchedule: growth " + std::to_string(schedule.growth) + " is below 2");
  }
  if (schedule.max_levels < 0) {
    throw Error("LevelSchedule: max_levels " + std::to_string(schedule.max_levels) +
                " is negative");
  }
  std::vector<Eigen::Index> ends;
  Eigen::Index end = 0;
  Eigen::Index size = schedule.first_level_size;
  while (end < count) {
    const bool last =
        schedule.max_levels > 0 && static_cast<int>(ends.size()) + 1 == schedule.max_levels;
    end = last || size >= count - end ? count : end + size;
    ends.push_back(end);
    // Saturate rather than overflow: a level that large is the last one anyway.
    size = size > std::numeric_limits<Eigen::Index>::max() / schedule.growth
               ? std::numeric_limits<Eigen::Index>::max()
               : size * schedule.growth;
  }
  return ends;
}

Pointshell nested_pointshell(const Pointshell& pointshell, const NestedLevelOptions& options) {
  validate(pointshell);
  const Eigen::Index count = pointshell.size();
  std::vector<Eigen::Index> ends = level_ends(count, options.schedule);
  const auto first = static_cast<Eigen::Index>(detail::split_mix(options.seed) %
                                               static_cast<std::uint64_t>(count));
  const FarthestPointOrder order = farthest_point_order(pointshell.points, first, options.progress);

  Pointshell nested;
  nested.points.resize(count, 3);
  nested.normals.resize(count, 3);
  for (Eigen::Index k = 0; k < count; ++k) {
    const Eigen::Index s = order.order[static_cast<std::size_t>(k)];
    nested.points.row(k) = pointshell.points.row(s);
    nested.normals.row(k) = pointshell.normals.row(s);
  }
  nested.level_ends = std::move(ends);
  return nested;
}

}  // namespace khz::contact
