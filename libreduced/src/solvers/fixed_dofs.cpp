#include <khz/reduced/errors.hpp>
#include <khz/reduced/solvers/fixed_dofs.hpp>

#include <string>

namespace khz::reduced {

FixedDofs::FixedDofs(Eigen::Index num_vertices, std::span<const int> fixed_vertices) {
  if (num_vertices < 0) {
    throw Error("number of vertices is negative (" + std::to_string(num_vertices) + ")");
  }
  std::vector<bool> fixed(static_cast<std::size_t>(num_vertices), false);
  for (const int v : fixed_vertices) {
    if (v < 0 || v >= num_vertices) {
      throw Error("fixed vertex " + std::to_string(v) + " is outside [0, " +
                  std::to_string(num_vertices) + ")");
    }
    fixed[static_cast<std::size_t>(v)] = true;
  }
  m_full_to_free.assign(static_cast<std::size_t>(3 * num_vertices), -1);
  for (std::size_t dof = 0; dof < m_full_to_free.size(); ++dof) {
    if (fixed[dof / 3]) continue;
    m_full_to_free[dof] = static_cast<int>(m_free_to_full.size());
    m_free_to_full.push_back(static_cast<int>(dof));
  }
}

Eigen::Index FixedDofs::num_full_dofs() const noexcept {
  return static_cast<Eigen::Index>(m_full_to_free.size());
}

Eigen::Index FixedDofs::num_free_dofs() const noexcept {
  return static_cast<Eigen::Index>(m_free_to_full.size());
}

bool FixedDofs::is_fixed(Eigen::Index vertex) const noexcept {
  return m_full_to_free[static_cast<std::size_t>(3 * vertex)] < 0;
}

Eigen::VectorXd FixedDofs::restrict_vector(const Eigen::VectorXd& full) const {
  if (full.size() != num_full_dofs()) {
    throw Error("full vector has " + std::to_string(full.size()) + " entries, expected " +
                std::to_string(num_full_dofs()));
  }
  return full(m_free_to_full);
}

void FixedDofs::expand_vector(const Eigen::VectorXd& free, Eigen::VectorXd& full) const {
  if (free.size() != num_free_dofs()) {
    throw Error("free vector has " + std::to_string(free.size()) + " entries, expected " +
                std::to_string(num_free_dofs()));
  }
  full.setZero(num_full_dofs());
  full(m_free_to_full) = free;
}

Eigen::MatrixXd FixedDofs::restrict_rows(const Eigen::MatrixXd& full) const {
  if (full.rows() != num_full_dofs()) {
    throw Error("full matrix has " + std::to_string(full.rows()) + " rows, expected " +
                std::to_string(num_full_dofs()));
  }
  return full(m_free_to_full, Eigen::all);
}

Eigen::MatrixXd FixedDofs::expand_rows(const Eigen::MatrixXd& free) const {
  if (free.rows() != num_free_dofs()) {
    throw Error("free matrix has " + std::to_string(free.rows()) + " rows, expected " +
                std::to_string(num_free_dofs()));
  }
  Eigen::MatrixXd full = Eigen::MatrixXd::Zero(num_full_dofs(), free.cols());
  full(m_free_to_full, Eigen::all) = free;
  return full;
}

void FixedDofs::check_full_matrix(const SparseMatrix& full) const {
  if (full.rows() != num_full_dofs() || full.cols() != num_full_dofs()) {
    throw Error("full matrix is " + std::to_string(full.rows()) + "×" +
                std::to_string(full.cols()) + ", expected " + std::to_string(num_full_dofs()) +
                "×" + std::to_string(num_full_dofs()));
  }
}

SparseMatrix FixedDofs::restrict_matrix(const SparseMatrix& full) const {
  check_full_matrix(full);
  // Free rows keep their order, so each restricted column is its full column with the fixed
  // rows dropped: count, then fill the compressed arrays directly.
  const Eigen::Index n = num_free_dofs();
  SparseMatrix restricted(n, n);
  Eigen::Index entries = 0;
  for (const int column : m_free_to_full) {
    for (SparseMatrix::InnerIterator it(full, column); it; ++it) {
      if (m_full_to_free[static_cast<std::size_t>(it.index())] >= 0) ++entries;
    }
  }
  restricted.resizeNonZeros(entries);
  int k = 0;
  for (Eigen::Index j = 0; j < n; ++j) {
    restricted.outerIndexPtr()[j] = k;
    for (SparseMatrix::InnerIterator it(full, m_free_to_full[static_cast<std::size_t>(j)]); it;
         ++it) {
      const int row = m_full_to_free[static_cast<std::size_t>(it.index())];
      if (row < 0) continue;
      restricted.innerIndexPtr()[k] = row;
      restricted.valuePtr()[k] = it.value();
      ++k;
    }
  }
  restricted.outerIndexPtr()[n] = k;
  return restricted;
}

void FixedDofs::restrict_matrix_values(const SparseMatrix& full, SparseMatrix& restricted) const {
  check_full_matrix(full);
  const Eigen::Index n = num_free_dofs();
  if (restricted.rows() != n || restricted.cols() != n) {
    throw Error("restricted matrix is " + std::to_string(restricted.rows()) + "×" +
                std::to_string(restricted.cols()) + ", expected " + std::to_string(n) + "×" +
                std::to_string(n));
  }
  // Walk each full column and its restricted column together (restrict_matrix's order); every
  // entry is checked, so a matrix with another pattern is rejected instead of garbled.
  for (Eigen::Index j = 0; j < n; ++j) {
    SparseMatrix::InnerIterator target(restricted, j);
    for (SparseMatrix::InnerIterator it(full, m_free_to_full[static_cast<std::size_t>(j)]); it;
         ++it) {
      const int row = m_full_to_free[static_cast<std::size_t>(it.index())];
      if (row < 0) continue;
      if (!target || target.index() != row) {
        throw Error("restricted matrix lacks entry (" + std::to_string(row) + ", " +
                    std::to_string(j) + ") of the full matrix's pattern");
      }
      target.valueRef() = it.value();
      ++target;
    }
    if (target) {
      throw Error("restricted matrix has entry (" + std::to_string(target.index()) + ", " +
                  std::to_string(j) + ") outside the full matrix's pattern");
    }
  }
}

std::vector<int> vertices_in_box(const VertexMatrix& vertices, const Eigen::AlignedBox3d& box) {
  std::vector<int> inside;
  for (Eigen::Index v = 0; v < vertices.rows(); ++v) {
    if (box.contains(vertices.row(v).transpose())) inside.push_back(static_cast<int>(v));
  }
  return inside;
}

}  // namespace khz::reduced
