#pragma once
// How an object's multi-resolution pointshell is made.

#include <khz/contact/pointshell/nested_levels.hpp>
#include <khz/contact/pointshell/repulsion_pointshell.hpp>

#include <Eigen/Core>

namespace khz::scene {

/// JSON object.pointshell.method.
enum class PointshellMethod {
  /// "repulsion": particle repulsion on the zero level set of the object's field (the `field`
  /// settings), n₀·4ⁱ points on level i (contact::repulsion_pointshell, §3.8.1). The default.
  repulsion,
  /// "vertices": the mesh's vertices (contact::vertex_pointshell), then nested levels.
  vertices,
  /// "random": area-uniform random surface points (contact::random_pointshell), then nested
  /// levels.
  random,
  /// "voxels": centres of the voxels touching the surface (contact::voxel_pointshell), then
  /// nested levels.
  voxels,
};

/// JSON object.pointshell. Which keys apply depends on the method; the reader refuses the
/// others. The settings of the library's structs keep the library's defaults and names.
struct PointshellDescription {
  PointshellMethod method = PointshellMethod::repulsion;  ///< "method".

  /// repulsion: "first_level_points" (n₀ ≥ 1), "levels" (L ≥ 1), "seed", "max_iterations"
  /// (≥ 1 per level), "tolerance" (in (0, 1)), "radius_factor" (κ in [1, 4]). Instead of
  /// first_level_points the file may give "points", the total N wanted in all levels:
  /// n₀ = max(1, round(3N / (4ᴸ − 1))). At most 2³¹ − 1 points in all. projection_tolerance
  /// and progress are not keys.
  contact::RepulsionOptions repulsion;

  /// vertices, random, voxels: the farthest-point order nested_pointshell() cuts into levels:
  /// "seed", and the schedule (contact::LevelSchedule) as "first_level_points" →
  /// first_level_size (≥ 1), "growth" (≥ 2), "levels" → max_levels (≥ 0; 0: as many as the
  /// points fill). For random the seed also draws the samples. progress is not a key.
  contact::NestedLevelOptions nested;
  /// "points": random only, required: the samples drawn (random_pointshell's count), in
  /// [1, 2³¹ − 1].
  Eigen::Index count = 0;
  /// "cell_size": voxels only, required: the voxels' side (m), > 0.
  double cell_size = 0.0;
};

}  // namespace khz::scene
