#pragma once
// Nearest-neighbour distances of a point set: how uniform a pointshell level is.

#include <khz/contact/common.hpp>

#include <Eigen/Core>

namespace khz::contact::detail {

/// Over every point of a set, the distance to its nearest other point (m).
struct NearestNeighbourStatistics {
  double min = 0.0;
  double max = 0.0;
  double mean = 0.0;
  double percentile_1 = 0.0;   ///< 1% of the points have a nearer neighbour.
  double percentile_99 = 0.0;  ///< 99% of the points have a nearer neighbour.
};

/// The statistics of rows [0, count) of `points`, whose mean spacing is about `spacing` (m),
/// found on a hash grid in parallel (OpenMP) and reproducibly. All zero if count < 2.
NearestNeighbourStatistics nearest_neighbour_statistics(const PointMatrix& points,
                                                        Eigen::Index count, double spacing);

}  // namespace khz::contact::detail
