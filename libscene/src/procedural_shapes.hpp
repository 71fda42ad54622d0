#pragma once
// The procedural shapes' readers (procedural_shape.hpp documents the shapes): each reads its
// parameters from a spec, checking them, and returns the generator of the mesh they describe.

#include "shape_arguments.hpp"

#include <khz/reduced/mesh/triangle_mesh.hpp>

#include <functional>

namespace khz::scene::detail {

/// Makes the mesh a spec describes, from the parameters its reader read.
using ShapeGenerator = std::function<reduced::TriangleMesh()>;

/// alpha_tube: loop, radius, sides, segments. @throws reduced::Error as ShapeArguments.
ShapeGenerator read_alpha_tube(ShapeArguments& arguments);
/// peg: side, length, chamfer. @throws reduced::Error as ShapeArguments.
ShapeGenerator read_peg(ShapeArguments& arguments);
/// plate_with_hole: side, thickness, hole. @throws reduced::Error as ShapeArguments.
ShapeGenerator read_plate_with_hole(ShapeArguments& arguments);

}  // namespace khz::scene::detail
