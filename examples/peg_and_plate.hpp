#pragma once
// The contact products of the procedural peg and plate with a hole (khz::scene::procedural_shape,
// default sizes), coarse enough to build in a fraction of a second: what the haptic examples
// hold and touch.
//   plate_with_hole: 10 cm square, z in [−0.02, 0], a 20.8 mm square hole at the centre;
//   peg: 2 cm square, z in [0, 0.08], chamfered at the bottom.
#include <khz/contact/field/mesh_distance_field.hpp>
#include <khz/contact/pointshell/repulsion_pointshell.hpp>
#include <khz/contact/tree/point_tree.hpp>
#include <khz/scene/procedural_shape.hpp>

namespace khz::examples {

/// Both products' settings: a 64³ field; 64 · 4ⁱ repulsion points on 3 levels.
inline contact::DistanceFieldOptions coarse_field() {
  contact::DistanceFieldOptions options;
  options.cells = 64;
  return options;
}

/// The plate's signed distance field (m, body frame).
inline contact::DistanceGrid plate_field() {
  return contact::signed_distance_field(scene::procedural_shape("plate_with_hole"), coarse_field());
}

/// The peg's pointshell as a point tree (body frame).
inline contact::PointTree peg_tree() {
  contact::RepulsionOptions repulsion;
  repulsion.first_level_points = 64;
  repulsion.levels = 3;
  return contact::PointTree(
      contact::repulsion_pointshell(scene::procedural_shape("peg"), coarse_field(), repulsion));
}

}  // namespace khz::examples
