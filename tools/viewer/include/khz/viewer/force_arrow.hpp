#pragma once
// How long the viewer draws a contact force: to scale while small, and never out of view.

#include <khz/render/camera.hpp>

#include <Eigen/Core>

namespace khz::viewer {

/// The force arrow's scale. The rule: an arrow for a force of magnitude F (N) is
///
///     length(F) = max_length · tanh(F · reference_length / (reference_force · max_length))   (m)
///
/// along the force. For small forces this is the frame pictures' linear scale (reference_force
/// drawn reference_length long: run::FrameRenderer draws the coupling's saturation force as
/// long as the scene's radius); as F grows the length rises ever more slowly towards
/// max_length. So the length grows with F (until tanh rounds to 1) and never exceeds
/// max_length: with max_length at most room_in_view() from the arrow's start along the force,
/// the arrow stays in view whatever the force (the overlay gives the force's value).
struct ArrowScale {
  double reference_force = 1.0;   ///< N, > 0.
  double reference_length = 1.0;  ///< m, > 0: the length of reference_force on the linear scale.
  double max_length = 1.0;        ///< m, > 0: the bound of every length.

  /// length(F) (m) for a magnitude F ≥ 0 (N); 0 for a negative or NaN F, max_length for +∞.
  double length(double force) const noexcept;
  /// The arrow of `force` (N, world): its direction, length(|force|) long (m); zero for a zero
  /// or non-finite force.
  Eigen::Vector3d arrow(const Eigen::Vector3d& force) const noexcept;
};

/// Half the smaller side of what `camera` sees at the depth of `point` (m, world): the distance
/// from the image's centre to its nearer edge, at that depth. 0 for a point behind the eye.
double view_half_extent(const render::Camera& camera, const Eigen::Vector3d& point) noexcept;

/// How far (m) one can go from `from` along `direction` (world, unit) and still be seen by
/// `camera` at least `margin` pixels inside the image's edges and beyond its near distance: the
/// largest t with from + t · direction there (the image of a segment is a segment, so all of it
/// is then in view). +∞ if nothing stops the way (a direction away from the eye, into the
/// view); 0 if `from` itself is not there or an input is not finite.
double room_in_view(const render::Camera& camera, const Eigen::Vector3d& from,
                    const Eigen::Vector3d& direction, double margin) noexcept;

}  // namespace khz::viewer
