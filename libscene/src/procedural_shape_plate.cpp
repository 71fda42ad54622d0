// plate_with_hole: a square plate with a square hole through it (procedural_shape.hpp).
#include "procedural_shapes.hpp"
#include "ring_loft.hpp"

namespace khz::scene::detail {

ShapeGenerator read_plate_with_hole(ShapeArguments& arguments) {
  const double side = arguments.number("side", 0.1, above(0.0));
  const double thickness = arguments.number("thickness", 0.02, above(0.0));
  const double hole =
      arguments.number("hole", 0.0208,
                       with_text(open_interval(0.0, side),
                                 "a number in (0, " + format_number(side) + ") (below side)"));
  return [=] {
    // Around the plate's section: up the outer wall, in across the top, down the hole's wall,
    // out across the bottom.
    reduced::VertexMatrix points(16, 3);
    points << square_ring(side / 2.0, -thickness), square_ring(side / 2.0, 0.0),
        square_ring(hole / 2.0, 0.0), square_ring(hole / 2.0, -thickness);
    return loft_cyclic(points, 4);
  };
}

}  // namespace khz::scene::detail
