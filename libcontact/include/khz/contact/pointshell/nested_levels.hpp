#pragma once
// Nested levels for a pointshell that came without them (vertices, random or voxel samples):
// farthest-point order cut into levels of growing size (thesis §3.9.1).

#include <khz/contact/common.hpp>
#include <khz/contact/export.hpp>
#include <khz/contact/pointshell/pointshell.hpp>

#include <Eigen/Core>

#include <cstdint>
#include <vector>

namespace khz::contact {

/// How many points each level gets: level i holds first_level_size · growthⁱ points, except the
/// last, which holds what remains (possibly fewer).
struct LevelSchedule {
  Eigen::Index first_level_size = 8;  ///< n₀ ≥ 1.
  int growth = 8;                     ///< ≥ 2.
  /// 0: as many levels as the points fill; otherwise at most this many (the last one then takes
  /// all remaining points).
  int max_levels = 0;

  /// Branching factor B (thesis §3.9.1, which used B = 8): B points, then B², B³, …
  static LevelSchedule branching(int factor) { return {factor, factor, 0}; }
  /// n₀ points, then four times as many per level: the sizes of particle-repulsion pointshells
  /// (§3.8.1), where each level halves the point spacing.
  static LevelSchedule quadrupling(Eigen::Index first_level_size) {
    return {first_level_size, 4, 0};
  }
};

/// The end (exclusive) of each level for `count` points under `schedule`, in the form of
/// Pointshell::level_ends: increasing, the last entry `count`.
/// @throws Error if count < 1, first_level_size < 1, growth < 2 or max_levels < 0.
KHZ_CONTACT_API std::vector<Eigen::Index> level_ends(Eigen::Index count,
                                                     const LevelSchedule& schedule);

/// Options of nested_pointshell().
struct NestedLevelOptions {
  LevelSchedule schedule;
  /// Picks the first point of the farthest-point order (reproducibly: same seed, same points,
  /// same result on every run and thread count of a build).
  std::uint64_t seed = 0;
  /// Reports stage "farthest-point order"; cancel by returning false.
  ProgressCallback progress;
};

/// The points and normals of `pointshell` (whose own levels are ignored: it may be a flat,
/// single-level set) reordered by farthest_point_order() and cut into levels by
/// level_ends(): every prefix of levels 0…i samples the whole surface, at a covering radius that
/// shrinks with i (thesis §3.9.1).
/// @throws Error if `pointshell` fails validate() or the schedule is invalid; Cancelled.
KHZ_CONTACT_API Pointshell nested_pointshell(const Pointshell& pointshell,
                                             const NestedLevelOptions& options = {});

}  // namespace khz::contact
