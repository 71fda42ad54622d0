#pragma once
// Named per-point arrays ("point data") written with the points of a .vtp file.

#include <khz/reduced/mesh/triangle_mesh.hpp>

#include <Eigen/Core>

#include <cstdint>
#include <string>
#include <variant>

namespace khz::series {

/// One byte per point, e.g. a state code (0 untouched, 1 traversed, 2 in contact).
using ByteVector = Eigen::Matrix<std::uint8_t, Eigen::Dynamic, 1>;

/// The values of a point-data array, one row per point: a scalar as a double, an int or a byte
/// (written as VTK Float64, Int32 and UInt8), or a 3-vector of doubles (Float64 with three
/// components) such as a displacement, a normal or a force, in the units of the caller.
using PointValues =
    std::variant<Eigen::VectorXd, Eigen::VectorXi, ByteVector, reduced::VertexMatrix>;

/// A named per-point array. It owns its values: std::move a matrix in to avoid the copy.
struct PointArray {
  /// The name ParaView shows: non-empty, unique within a file, without control characters
  /// (written XML-escaped, so '&', '<', '"' and spaces are fine).
  std::string name;
  /// One row per point of the file the array is written with.
  PointValues values;
};

}  // namespace khz::series
