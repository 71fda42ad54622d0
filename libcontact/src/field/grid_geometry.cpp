#include <khz/contact/common.hpp>
#include <khz/contact/field/grid_geometry.hpp>

#include <cmath>
#include <string>

namespace khz::contact {

GridGeometry GridGeometry::cube_around(const Eigen::AlignedBox3d& bounds, double expansion,
                                       int cells) {
  if (bounds.isEmpty() || !bounds.min().allFinite() || !bounds.max().allFinite()) {
    throw Error("GridGeometry::cube_around: the bounding box is empty or not finite");
  }
  if (!(expansion >= 1.0) || !std::isfinite(expansion)) {
    throw Error("GridGeometry::cube_around: the expansion factor must be at least 1, got " +
                std::to_string(expansion));
  }
  if (cells < 1) {
    throw Error("GridGeometry::cube_around: cells must be at least 1, got " +
                std::to_string(cells));
  }
  double edge = expansion * bounds.sizes().maxCoeff();
  if (!(edge > 0.0)) edge = 1.0;  // a single point: any cube around it will do
  GridGeometry geometry;
  geometry.cells = cells;
  geometry.spacing = edge / cells;
  geometry.origin = bounds.center() - Eigen::Vector3d::Constant(0.5 * edge);
  return geometry;
}

void GridGeometry::validate() const {
  if (!origin.allFinite()) throw Error("GridGeometry: the origin is not finite");
  if (!(spacing > 0.0) || !std::isfinite(spacing)) {
    throw Error("GridGeometry: the spacing must be positive and finite, got " +
                std::to_string(spacing));
  }
  if (cells < 1)
    throw Error("GridGeometry: cells must be at least 1, got " + std::to_string(cells));
}

}  // namespace khz::contact
