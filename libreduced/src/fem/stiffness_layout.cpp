#include "fem/stiffness_layout.hpp"

#include <khz/reduced/errors.hpp>

#include <algorithm>
#include <cstdint>
#include <limits>
#include <string>

namespace khz::reduced::detail {

StiffnessLayout build_stiffness_layout(const ElementMatrix& elements, int num_vertices) {
  const int num_elements = static_cast<int>(elements.rows());
  const int nodes = static_cast<int>(elements.cols());

  // Sorted, unique neighbours of every vertex (itself included), as CSR.
  std::vector<std::vector<int>> neighbours(num_vertices);
  for (int e = 0; e < num_elements; ++e) {
    for (int b = 0; b < nodes; ++b) {
      for (int a = 0; a < nodes; ++a) neighbours[elements(e, b)].push_back(elements(e, a));
    }
  }
  std::int64_t nonzeros = 0;
  for (auto& list : neighbours) {
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
    nonzeros += 9 * static_cast<std::int64_t>(list.size());
  }
  // valuePtr() positions are int (the matrix's StorageIndex).
  if (nonzeros > std::numeric_limits<int>::max()) {
    throw Error("stiffness matrix would have " + std::to_string(nonzeros) +
                " entries, more than its int indices can address");
  }

  StiffnessLayout layout;
  const int dofs = 3 * num_vertices;
  layout.pattern.resize(dofs, dofs);
  layout.pattern.resizeNonZeros(static_cast<Eigen::Index>(nonzeros));
  int* outer = layout.pattern.outerIndexPtr();
  int* inner = layout.pattern.innerIndexPtr();
  layout.column_stride.resize(num_vertices);
  int position = 0;
  for (int b = 0; b < num_vertices; ++b) {
    layout.column_stride[b] = 3 * static_cast<int>(neighbours[b].size());
    for (int k = 0; k < 3; ++k) {
      outer[3 * b + k] = position;
      for (const int a : neighbours[b]) {
        for (int i = 0; i < 3; ++i) inner[position++] = 3 * a + i;
      }
    }
  }
  outer[dofs] = position;
  layout.pattern.coeffs().setZero();

  layout.block_positions.resize(static_cast<std::size_t>(num_elements) * nodes * nodes);
  for (int e = 0; e < num_elements; ++e) {
    for (int b = 0; b < nodes; ++b) {
      const int vb = elements(e, b);
      const auto& list = neighbours[vb];
      for (int a = 0; a < nodes; ++a) {
        const auto found = std::lower_bound(list.begin(), list.end(), elements(e, a));
        layout.block_positions[(static_cast<std::size_t>(e) * nodes + b) * nodes + a] =
            outer[3 * vb] + 3 * static_cast<int>(found - list.begin());
      }
    }
  }
  return layout;
}

}  // namespace khz::reduced::detail
