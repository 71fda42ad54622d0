#pragma once
// Procedural surface meshes named by a short text spec, "NAME" or "NAME:KEY=VALUE,KEY=VALUE"
// (e.g. "peg:side=0.02,length=0.08"): closed demo and benchmark shapes that a scene names as
// "mesh": "shape:SPEC" and `khz shape SPEC OUT` writes to a file.
//
// Every shape is a closed, 2-manifold, consistently outward-oriented (counter-clockwise seen from
// outside) triangle mesh without self-intersections, in units of its own parameters (metres in a
// scene with scale 1). The shapes and their parameters (defaults in brackets):
//
// alpha_tube — one piece of an Alpha-puzzle-like pair: a tube of circular section swept along an
// "α" curve, a loop whose two ends cross each other (offset out of its plane) and run on as two
// short tails, with hemispherical ends.
//   loop [1]: the loop's width (its centreline's extent along x), > 0.
//   radius [loop/10]: the tube's radius, in (0, loop/8].
//   sides [32]: vertices around the tube, an integer in [8, 256].
//   segments [256]: steps of equal arc length along the centreline, an integer in [16, 8192].
// Centreline, for t in [−τ, τ], k = 1.3, τ = 1.15, r = radius:
//   c(t) = (loop (t² − ½), loop k t (t² − 1), 1.5 r sin(π/2 · clamp(t, −1, 1))).
// The loop, t in [−1, 1], spans x in [−loop/2, loop/2] and tilts from z = −1.5r to 1.5r; its ends
// cross at (loop/2, 0) with their centrelines 3r apart, so the gap between them (r) is narrower
// than a tube (2r). The tails, |t| in [1, τ], stay at z = ±1.5r. The tube is every point within
// r of the centreline, its vertices on that surface: rings of `sides` vertices at segments + 1
// equal arc-length steps and ⌈sides/4⌉ − 1 latitude rings plus a pole on each hemispherical end.
// Centreline length ≈ 4.235 loop (at r = loop/10). Bounding box (the centreline's, grown by r):
//   x in [−loop/2 − r, 0.8225 loop + r], y in ±(0.50037 loop + r) (0.50037 = 2k/√27),
//   z in ±2.5r; with the defaults [−0.6, 0.9225] × [−0.6004, 0.6004] × [−0.25, 0.25], the radius
//   1/15.2 of the longest side. Defaults: 8,674 vertices, 17,344 triangles.
// Interlocked pose: a second copy with the same parameters, rotated 180° about the axis
// (0, 1, −1) and moved to (−loop/2, 0, 0) — (x, y, z) ↦ (−x − loop/2, −z, −y) — hangs in the
// first like a chain link: each loop's far end (t = 0) passes through the middle of the other's
// loop. The two surfaces stay at least 0.16 loop apart (radius loop/10; 0.10 loop at loop/8),
// and neither copy can leave the other by a translation along x, y or z: each direction meets
// the other tube within 0.31 loop (radius loop/10; within half a loop at any radius). In a scene
// (both objects with "centre": false and the same scale s) the second object's pose is {"position":
// [−loop/2 · s, 0, 0], "rotation":
// {"axis": [0, 1, −1], "degrees": 180}}.
//
// peg — a square box peg along z with its bottom edges chamfered.
//   side [0.02]: the square section's side, > 0.
//   length [0.08]: along z, > 0.
//   chamfer [0.001]: the 45° chamfer's width on the four bottom edges, in [0, side/2) and
//   < length.
// x, y in [−side/2, side/2], z in [0, length]; the bottom face (z = 0) is the square of side
// side − 2 chamfer. Volume side² length − 2 chamfer² side + 4/3 chamfer³. 14 vertices,
// 24 triangles (flat faces, no subdivision).
//
// plate_with_hole — a square plate with a square hole through it, for the peg.
//   side [0.1]: the plate's side, > 0.
//   thickness [0.02]: along z, > 0.
//   hole [0.0208]: the hole's side, in (0, side); the default is 1.04 times the default peg's.
// x, y in [−side/2, side/2], z in [−thickness, 0] (the top face at z = 0); the hole is
// [−hole/2, hole/2]² with its sides parallel to the plate's. Volume (side² − hole²) thickness.
// Genus 1: 16 vertices, 32 triangles. A peg of side p fits with clearance hole − p, (hole − p)/2
// on each side when centred: 0.0008 for the defaults. A peg at the identity pose stands with its
// chamfered bottom face on the hole's mouth (z = 0); lowered by d it is d deep in the hole.

#include <khz/reduced/mesh/triangle_mesh.hpp>
#include <khz/scene/export.hpp>

#include <span>
#include <string>
#include <string_view>

namespace khz::scene {

/// Version of the generators. Content keys carry it: it is bumped whenever the mesh some spec
/// produces changes (a vertex moves, a triangle changes), so products cached from the old mesh
/// stop matching.
inline constexpr int procedural_shape_version = 1;

/// The shapes procedural_shape() knows, sorted: "alpha_tube", "peg", "plate_with_hole".
KHZ_SCENE_API std::span<const std::string_view> procedural_shape_names() noexcept;

/// `spec` with every parameter written out in the shape's order (as listed above), defaults
/// filled in and numbers in their shortest exact form: "peg" and "peg:length=8e-2" both give
/// "peg:side=0.02,length=0.08,chamfer=0.001". Equal texts ⇔ equal meshes (for one
/// procedural_shape_version).
/// @throws reduced::Error as procedural_shape(), without generating anything.
KHZ_SCENE_API std::string canonical_shape_spec(std::string_view spec);

/// The mesh `spec` describes (see above): "NAME" or "NAME:KEY=VALUE,...", no spaces, each
/// parameter at most once, values as decimal or scientific numbers. Under a millisecond for the
/// defaults (alpha_tube: 17,344 triangles in 0.5 ms).
/// @throws reduced::Error for an unknown shape (listing the shapes), an unknown parameter (listing
///         the shape's parameters), a parameter given twice, text that is not KEY=VALUE, or a
///         value that is no number or out of its range; the message names the shape and the
///         parameter and says what was expected and what was found.
KHZ_SCENE_API reduced::TriangleMesh procedural_shape(std::string_view spec);

}  // namespace khz::scene
