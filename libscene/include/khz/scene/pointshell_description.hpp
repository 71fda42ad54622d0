#pragma once
// How an object's multi-resolution pointshell is made.

#include <khz/contact/pointshell/nested_levels.hpp>

#include <Eigen/Core>

#include <cstdint>

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
/// others.
struct PointshellDescription {
  PointshellMethod method = PointshellMethod::repulsion;  ///< "method".

  // --- repulsion (contact::RepulsionOptions, same names) ---
  /// "first_level_points": n₀ ≥ 1. Alternatively "points", the total N wanted in all levels:
  /// n₀ = max(1, round(3N / (4ᴸ − 1))). At most 2³¹ − 1 points in all.
  Eigen::Index first_level_points = 64;
  int levels = 4;              ///< "levels": L ≥ 1.
  int max_iterations = 1000;   ///< "max_iterations": ≥ 1 per level.
  double tolerance = 1e-3;     ///< "tolerance": in (0, 1).
  double radius_factor = 1.5;  ///< "radius_factor": κ in [1, 4].

  /// "seed": repulsion's starting positions (RepulsionOptions::seed); for the other methods the
  /// farthest-point order (NestedLevelOptions::seed) and, for random, the samples.
  std::uint64_t seed = 0;

  // --- vertices, random, voxels ---
  /// "points": random only, required: the samples drawn (random_pointshell's count), ≥ 1.
  Eigen::Index count = 0;
  /// "cell_size": voxels only, required: the voxels' side (m), > 0.
  double cell_size = 0.0;
  /// Level sizes of the farthest-point order (contact::LevelSchedule, nested_pointshell()):
  /// JSON "first_level_points" → first_level_size (default 8), "growth" (default 8, ≥ 2),
  /// "levels" → max_levels (default 0: as many as the points fill).
  contact::LevelSchedule schedule;
};

}  // namespace khz::scene
