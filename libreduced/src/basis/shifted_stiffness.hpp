#pragma once
// K − λM on blocks of vectors, each vector with its own shift λ: the operator of the
// unconstrained modal derivatives (thesis §2.8.7, eq. 2.60), applied once per MINRES iteration
// to every live right-hand side.

#include <khz/reduced/fem/fem_model.hpp>

#include <Eigen/Core>

#include <vector>

namespace khz::reduced::detail {

/// K and M on the union of their sparsity patterns, applied as Y = K X − M X diag(λ). Two
/// Eigen products would stream both matrices once per column of X; this streams the pattern
/// once per 8 columns, with the 8 values of each row of X contiguous (SIMD), and splits the rows
/// over worker_threads().
class ShiftedStiffness {
 public:
  /// @param stiffness, mass symmetric n × n (their columns are read as their rows).
  ShiftedStiffness(const SparseMatrix& stiffness, const SparseMatrix& mass);

  /// y = K x − M x diag(shifts): x n × m, shifts m, y resized to n × m.
  void apply(const Eigen::MatrixXd& x, const Eigen::VectorXd& shifts, Eigen::MatrixXd& y) const;

 private:
  SparseMatrix m_stiffness;           ///< K on the union pattern (explicit zeros where only M is)
  std::vector<double> m_mass_values;  ///< M on the same pattern, entry for entry
};

}  // namespace khz::reduced::detail
