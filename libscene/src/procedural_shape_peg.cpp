// peg: a square box peg along z with chamfered bottom edges (procedural_shape.hpp).
#include "procedural_shapes.hpp"
#include "ring_loft.hpp"

#include <algorithm>

namespace khz::scene::detail {

ShapeGenerator read_peg(ShapeArguments& arguments) {
  const double side = arguments.number("side", 0.02, above(0.0));
  const double length = arguments.number("length", 0.08, above(0.0));
  const double most = std::min(side / 2.0, length);
  const double chamfer =
      arguments.number("chamfer", 0.001,
                       with_text(half_open(0.0, most), "a number in [0, " + format_number(most) +
                                                           ") (below side/2 and length)"));
  return [=] {
    // Square rings upwards: the bottom face's outline (when chamfered), the chamfer's top, the
    // top face's outline.
    const int rings = chamfer > 0.0 ? 3 : 2;
    reduced::VertexMatrix points(4 * rings, 3);
    if (chamfer > 0.0) {
      points << square_ring(side / 2.0 - chamfer, 0.0), square_ring(side / 2.0, chamfer),
          square_ring(side / 2.0, length);
    } else {
      points << square_ring(side / 2.0, 0.0), square_ring(side / 2.0, length);
    }
    return loft_between_poles(points, 4, Eigen::RowVector3d(0.0, 0.0, 0.0),
                              Eigen::RowVector3d(0.0, 0.0, length));
  };
}

}  // namespace khz::scene::detail
