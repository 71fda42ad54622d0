#pragma once
// Invariant checks shared by the validate() overloads.

#include <khz/reduced/errors.hpp>
#include <khz/reduced/mesh/triangle_mesh.hpp>

#include <Eigen/Core>

#include <string>

namespace khz::reduced::detail {

/// @throws MeshError naming the first vertex with a non-finite coordinate.
inline void check_finite_vertices(const VertexMatrix& vertices) {
  for (Eigen::Index v = 0; v < vertices.rows(); ++v) {
    if (!vertices.row(v).allFinite()) {
      throw MeshError("vertex " + std::to_string(v) + " has a non-finite coordinate", v);
    }
  }
}

/// @throws MeshError naming the first `kind` row with an index outside [0, num_vertices).
template <typename Derived>
void check_indices(const Eigen::MatrixBase<Derived>& rows, Eigen::Index num_vertices,
                   const char* kind) {
  for (Eigen::Index r = 0; r < rows.rows(); ++r) {
    for (Eigen::Index c = 0; c < rows.cols(); ++c) {
      const auto index = rows(r, c);
      if (index < 0 || index >= num_vertices) {
        throw MeshError(std::string(kind) + " " + std::to_string(r) + " uses vertex " +
                            std::to_string(index) + ", outside [0, " +
                            std::to_string(num_vertices) + ")",
                        r);
      }
    }
  }
}

}  // namespace khz::reduced::detail
