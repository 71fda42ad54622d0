#include "pointshell/repulsion_projection.hpp"

#include <cmath>

namespace khz::contact::detail {

namespace {

constexpr int max_newton_steps = 16;
constexpr int max_halvings = 8;
constexpr int max_bisections = 60;
// A distance field's gradient has length 1; the trilinear one of a sampled field is much
// shorter only near medial sheets, where it cannot say which way the level set lies.
constexpr double least_gradient = 1e-3;

struct Sample {
  Eigen::Vector3d point;
  Eigen::Vector3d gradient;
  double residual;  ///< d(point) − level.
};

Sample sample(const DistanceGrid& field, double level, const Eigen::Vector3d& point) noexcept {
  Sample s{point, Eigen::Vector3d::Zero(), 0.0};
  s.residual = field.distance_and_gradient(point, s.gradient) - level;
  return s;
}

LevelSetProjection done(const Sample& s) noexcept {
  LevelSetProjection result;
  result.point = s.point;
  const double length = s.gradient.norm();
  result.converged = length > 0.0;
  if (result.converged) result.normal = s.gradient / length;
  return result;
}

/// Newton's method from `s`; true with `s` on the level set, false where it stalls.
bool newton(const DistanceGrid& field, double level, double tolerance, double max_step,
            Sample& s) noexcept {
  for (int step = 0; step < max_newton_steps; ++step) {
    if (std::abs(s.residual) <= tolerance) return true;
    const double length = s.gradient.norm();
    if (!(length >= least_gradient)) return false;
    Eigen::Vector3d move = (-s.residual / (length * length)) * s.gradient;
    const double move_length = move.norm();
    if (move_length > max_step) move *= max_step / move_length;
    bool decreased = false;
    for (int halving = 0; halving <= max_halvings && !decreased; ++halving, move *= 0.5) {
      const Sample trial = sample(field, level, s.point + move);
      if (std::abs(trial.residual) < std::abs(s.residual)) {
        s = trial;
        decreased = true;
      }
    }
    if (!decreased) return false;
  }
  return std::abs(s.residual) <= tolerance;
}

/// The fallback where Newton stalls (the trilinear gradient jumps between cells, and on
/// features no wider than a cell it can point far from the level set's normal): walk from `s`
/// along its gradient, towards the level, in doubling steps up to max_step until the residual
/// changes sign, then bisect — slow but sure, since the interpolated field is continuous.
bool bracket_and_bisect(const DistanceGrid& field, double level, double tolerance, double max_step,
                        Sample& s) noexcept {
  const double length = s.gradient.norm();
  if (!(length > 0.0)) return false;
  const Eigen::Vector3d direction = (s.residual > 0.0 ? -1.0 : 1.0) / length * s.gradient;
  double near = 0.0;
  double far = max_step / 64.0;
  Sample beyond = sample(field, level, s.point + far * direction);
  while ((beyond.residual > 0.0) == (s.residual > 0.0)) {
    if (far >= max_step) return false;
    near = far;
    far *= 2.0;
    beyond = sample(field, level, s.point + far * direction);
  }
  const Sample start = s;
  for (int bisection = 0; bisection < max_bisections; ++bisection) {
    if (std::abs(beyond.residual) <= tolerance) {
      s = beyond;
      return true;
    }
    const double middle = 0.5 * (near + far);
    const Sample half = sample(field, level, start.point + middle * direction);
    if ((half.residual > 0.0) == (start.residual > 0.0)) {
      near = middle;
    } else {
      far = middle;
      beyond = half;
    }
  }
  return false;
}

}  // namespace

LevelSetProjection project_onto_level_set(const DistanceGrid& field, double level,
                                          const Eigen::Vector3d& start, double tolerance,
                                          double max_step) noexcept {
  const Sample initial = sample(field, level, start);
  Sample s = initial;
  if (newton(field, level, tolerance, max_step, s)) return done(s);
  s = initial;
  if (bracket_and_bisect(field, level, tolerance, max_step, s)) return done(s);
  LevelSetProjection failed;
  failed.point = start;
  return failed;
}

}  // namespace khz::contact::detail
