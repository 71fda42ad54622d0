#pragma once
// The corners of a unit lattice cube, shared by the box generators and the voxelizer, so both
// emit hexahedra in the same (VTK) node order.

#include <Eigen/Core>

#include <array>

namespace khz::reduced::detail {

/// Offsets of a cube's corners from its lowest corner, in VTK hexahedron node order: the bottom
/// face counter-clockwise seen from +z, then the top face above it. This order is positively
/// oriented.
inline const std::array<Eigen::Vector3i, 8>& hex_corner_offsets() {
  static const std::array<Eigen::Vector3i, 8> offsets = {
      Eigen::Vector3i(0, 0, 0), Eigen::Vector3i(1, 0, 0), Eigen::Vector3i(1, 1, 0),
      Eigen::Vector3i(0, 1, 0), Eigen::Vector3i(0, 0, 1), Eigen::Vector3i(1, 0, 1),
      Eigen::Vector3i(1, 1, 1), Eigen::Vector3i(0, 1, 1)};
  return offsets;
}

}  // namespace khz::reduced::detail
