#pragma once
// Constraint stabilization of particle repulsion: moving a point back onto a level set of a
// distance field (thesis §3.8.1).

#include <khz/contact/field/distance_grid.hpp>

#include <Eigen/Core>

namespace khz::contact::detail {

/// Where a projection ended.
struct LevelSetProjection {
  Eigen::Vector3d point = Eigen::Vector3d::Zero();   ///< Final position (m).
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();  ///< Unit field gradient there.
  bool converged = false;                            ///< |d(point) − level| ≤ tolerance.
};

/// Newton's method for d(p) = level along the field's gradient ∇d: p ← p − (d − level)∇d/|∇d|²,
/// each step at most `max_step` long and halved until |d − level| decreases. Where it stalls
/// (the trilinear gradient jumps across cell faces, and vanishes near medial sheets), a search
/// along the starting gradient, in doubling steps up to `max_step`, brackets a change of sign
/// and bisects it. Fails — converged = false, `point` = start — only if neither reaches
/// |d − level| ≤ tolerance.
LevelSetProjection project_onto_level_set(const DistanceGrid& field, double level,
                                          const Eigen::Vector3d& start, double tolerance,
                                          double max_step) noexcept;

}  // namespace khz::contact::detail
