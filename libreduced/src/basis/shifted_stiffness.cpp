#include "shifted_stiffness.hpp"

#include <khz/reduced/worker_threads.hpp>

#include <algorithm>

namespace khz::reduced::detail {

namespace {

constexpr Eigen::Index kLanes = 8;  // columns per pass over the pattern
using Lanes = Eigen::Array<double, kLanes, 1>;

}  // namespace

ShiftedStiffness::ShiftedStiffness(const SparseMatrix& stiffness, const SparseMatrix& mass)
    : m_stiffness(stiffness + 0.0 * mass) {
  m_stiffness.makeCompressed();
  m_mass_values.assign(static_cast<std::size_t>(m_stiffness.nonZeros()), 0.0);
  // Both patterns are sorted within each column: merge M's entries into the union's.
  for (Eigen::Index column = 0; column < mass.outerSize(); ++column) {
    int entry = m_stiffness.outerIndexPtr()[column];
    for (SparseMatrix::InnerIterator it(mass, column); it; ++it) {
      while (m_stiffness.innerIndexPtr()[entry] != it.row()) ++entry;
      m_mass_values[static_cast<std::size_t>(entry)] = it.value();
    }
  }
}

void ShiftedStiffness::apply(const Eigen::MatrixXd& x, const Eigen::VectorXd& shifts,
                             Eigen::MatrixXd& y) const {
  const Eigen::Index n = x.rows();
  const Eigen::Index m = x.cols();
  y.resize(n, m);
  const int* outer = m_stiffness.outerIndexPtr();
  const int* inner = m_stiffness.innerIndexPtr();
  const double* stiffness = m_stiffness.valuePtr();
  const double* mass = m_mass_values.data();
  // Column j of `panel` is row j of the current 8 columns of x (zero past the last column).
  Eigen::Matrix<double, kLanes, Eigen::Dynamic> panel(kLanes, n);
#pragma omp parallel num_threads(worker_threads())
  for (Eigen::Index first = 0; first < m; first += kLanes) {
    const Eigen::Index width = std::min(kLanes, m - first);
    Lanes lambda = Lanes::Zero();
    lambda.head(width) = shifts.segment(first, width);
#pragma omp for schedule(static)
    for (Eigen::Index j = 0; j < n; ++j) {
      panel.col(j).setZero();
      panel.col(j).head(width) = x.row(j).segment(first, width).transpose();
    }
#pragma omp for schedule(static)
    for (Eigen::Index i = 0; i < n; ++i) {
      Lanes sum = Lanes::Zero();
      for (int p = outer[i]; p < outer[i + 1]; ++p) {
        sum += (stiffness[p] - lambda * mass[p]) * panel.col(inner[p]).array();
      }
      y.row(i).segment(first, width) = sum.head(width).transpose();
    }
  }
}

}  // namespace khz::reduced::detail
