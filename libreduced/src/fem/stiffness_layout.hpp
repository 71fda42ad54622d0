#pragma once
// The fixed sparsity pattern of the stiffness matrix and where each element's entries live in
// it, so assembly is a scatter into valuePtr() with no search and no allocation.

#include <khz/reduced/fem/fem_model.hpp>

#include <vector>

namespace khz::reduced::detail {

/// K's pattern has a full 3×3 block (both triangles) for every pair of vertices sharing an
/// element. Because blocks are full, the three columns 3b, 3b+1, 3b+2 of vertex b have the same
/// rows, and rows 3a..3a+2 of a block are adjacent in each column. Element entry (3a+i, 3b+k)
/// therefore lives at valuePtr()[block_position + k·column_stride[b] + i], which needs one
/// position per node pair instead of nine.
struct StiffnessLayout {
  SparseMatrix pattern;  ///< 3n×3n, compressed, all values zero.
  /// Per element, N² positions: entry [e·N² + b·N + a] is the index in valuePtr() of K's entry
  /// (3·node_a, 3·node_b), N = nodes per element.
  std::vector<int> block_positions;
  /// Per vertex, the entries in each of its three columns (3 × vertices it shares an element
  /// with, itself included).
  std::vector<int> column_stride;
};

StiffnessLayout build_stiffness_layout(const ElementMatrix& elements, int num_vertices);

}  // namespace khz::reduced::detail
