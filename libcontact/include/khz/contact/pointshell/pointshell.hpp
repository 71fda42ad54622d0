#pragma once
// A multi-resolution pointshell: points on a closed oriented surface with inward normals, in
// nested levels (thesis §3.8).

#include <khz/contact/common.hpp>
#include <khz/contact/export.hpp>

#include <Eigen/Core>

#include <vector>

namespace khz::contact {

/// Points sampling the contact surface of the pointshell object, with unit normals pointing into
/// the object (thesis §3.5: the force on a point in contact is −k_C d N), grouped into levels:
/// level 0 is the coarsest, and the points of levels 0…i together sample the whole surface at
/// resolution i (each level about four times as many points as the one before, §3.8.1). Points
/// are stored level after level.
struct KHZ_CONTACT_API Pointshell {
  PointMatrix points;   ///< N×3 positions (m), level 0 first.
  PointMatrix normals;  ///< N×3 unit inward normals.
  /// End (exclusive) of each level in `points`: level i is [level_ends[i−1], level_ends[i]), with
  /// level_ends[−1] = 0; the last entry is N.
  std::vector<Eigen::Index> level_ends;

  Eigen::Index size() const noexcept { return points.rows(); }
  int num_levels() const noexcept { return static_cast<int>(level_ends.size()); }
  Eigen::Index level_begin(int level) const noexcept {
    return level == 0 ? 0 : level_ends[level - 1];
  }
  Eigen::Index level_end(int level) const noexcept { return level_ends[level]; }
};

/// Checks what every consumer relies on: as many normals as points, finite values, unit normals
/// (to 1e-6), at least one level, level ends increasing, each level non-empty, the last at N.
/// @throws Error naming the first violation.
KHZ_CONTACT_API void validate(const Pointshell& pointshell);

}  // namespace khz::contact
