#pragma once
// Expressing one sparse matrix on another's (larger) pattern, so sums like αM + βK can be formed
// value-array by value-array inside Newton loops, without allocating.

#include <khz/reduced/errors.hpp>
#include <khz/reduced/fem/fem_model.hpp>

#include <algorithm>
#include <string>

namespace khz::reduced::detail {

/// The value array of a compressed sparse matrix, as a vector to compute with.
inline Eigen::Map<Eigen::VectorXd> values_of(SparseMatrix& matrix) {
  return {matrix.valuePtr(), matrix.nonZeros()};
}
inline Eigen::Map<const Eigen::VectorXd> values_of(const SparseMatrix& matrix) {
  return {matrix.valuePtr(), matrix.nonZeros()};
}

/// The values of `matrix` laid out on `pattern`'s value array (zeros where `matrix` has no
/// entry). @throws Error if `matrix` has an entry outside `pattern`.
inline Eigen::VectorXd values_on_pattern(const SparseMatrix& matrix, const SparseMatrix& pattern) {
  Eigen::VectorXd values = Eigen::VectorXd::Zero(pattern.nonZeros());
  for (Eigen::Index col = 0; col < matrix.outerSize(); ++col) {
    const int* begin = pattern.innerIndexPtr() + pattern.outerIndexPtr()[col];
    const int* end = pattern.innerIndexPtr() + pattern.outerIndexPtr()[col + 1];
    for (SparseMatrix::InnerIterator it(matrix, col); it; ++it) {
      const int* found = std::lower_bound(begin, end, static_cast<int>(it.row()));
      if (found == end || *found != it.row()) {
        throw Error("matrix entry (" + std::to_string(it.row()) + ", " + std::to_string(col) +
                    ") lies outside the target sparsity pattern");
      }
      values[found - pattern.innerIndexPtr()] += it.value();
    }
  }
  return values;
}

}  // namespace khz::reduced::detail
