#include "../detail/thread_limited_call.hpp"

#include <khz/reduced/errors.hpp>
#include <khz/reduced/solvers/sparse_cholesky.hpp>

#include <cholmod.h>

#include <algorithm>
#include <limits>
#include <new>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

namespace khz::reduced {

namespace {

// A singular matrix rarely yields an exact zero pivot: rounding leaves a pivot of about
// ε·‖A‖ times the number of updates it received, which grows with the matrix. Pivots whose
// ratio (CHOLMOD's rcond: min/max of |diag D|, or of diag L squared) falls below n·ε are taken
// for such a remnant. The ratio is at least 1/cond(A) for positive definite A, so only matrices
// with cond(A) > 1/(n·ε) (≈ 4.5e9 for a million unknowns) can be rejected wrongly, and their
// solutions would have few correct digits anyway. Measured on singular grid Laplacians: rcond
// 7e-17 (n = 64), 1e-14 (n = 1000), 1.2e-13 (n = 27000), all below n·ε.
double singular_rcond(Eigen::Index size) {
  return static_cast<double>(std::max<Eigen::Index>(size, 1)) *
         std::numeric_limits<double>::epsilon();
}

std::string cholmod_status_text(int status) {
  switch (status) {
    case CHOLMOD_OUT_OF_MEMORY:
      return "out of memory";
    case CHOLMOD_TOO_LARGE:
      return "problem too large";
    case CHOLMOD_INVALID:
      return "invalid input";
    default:
      return "status " + std::to_string(status);
  }
}

// CHOLMOD reports a failure through Common->status (printing is off); turn a fatal one into
// the matching exception.
void throw_if_failed(const cholmod_common& common, const char* operation) {
  if (common.status >= CHOLMOD_OK) return;
  if (common.status == CHOLMOD_OUT_OF_MEMORY) throw std::bad_alloc();
  throw SolverError(std::string("CHOLMOD ") + operation +
                    " failed: " + cholmod_status_text(common.status));
}

}  // namespace

struct SparseCholesky::Data {
  explicit Data(Kind k) : kind(k) {
    cholmod_start(&common);
    common.print = 0;  // failures reach the caller as exceptions, not as text on stdout
    if (kind == Kind::llt) {
      // Simplicial factorizations are LLᵀ too, so a non-positive pivot is detected whichever
      // method CHOLMOD picks; supernodal ones stop at the first failing supernode.
      common.final_ll = 1;
      common.quick_return_if_not_posdef = 1;
    } else {
      common.supernodal = CHOLMOD_SIMPLICIAL;  // CHOLMOD's supernodal method is LLᵀ only
      common.final_ll = 0;
    }
  }
  ~Data() {
    cholmod_free_dense(&solution, &common);
    cholmod_free_dense(&workspace_y, &common);
    cholmod_free_dense(&workspace_e, &common);
    cholmod_free_factor(&factor, &common);
    cholmod_finish(&common);
  }
  Data(const Data&) = delete;
  Data& operator=(const Data&) = delete;

  // A view of an Eigen matrix as a cholmod_sparse, sharing its arrays. CHOLMOD reads but never
  // writes its input matrix, which makes the const_casts safe.
  cholmod_sparse view(const SparseMatrix& matrix) const {
    cholmod_sparse a{};
    a.nrow = static_cast<std::size_t>(matrix.rows());
    a.ncol = static_cast<std::size_t>(matrix.cols());
    a.nzmax = static_cast<std::size_t>(matrix.outerIndexPtr()[matrix.outerSize()]);
    a.p = const_cast<int*>(matrix.outerIndexPtr());
    a.i = const_cast<int*>(matrix.innerIndexPtr());
    a.nz = matrix.isCompressed() ? nullptr : const_cast<int*>(matrix.innerNonZeroPtr());
    a.x = const_cast<double*>(matrix.valuePtr());
    // Which triangle CHOLMOD reads: the upper for llt (its supernodal method then needs one
    // permuted transpose instead of two), the lower for the simplicial ldlt (likewise).
    a.stype = kind == Kind::llt ? 1 : -1;
    a.itype = CHOLMOD_INT;
    a.xtype = CHOLMOD_REAL;
    a.dtype = CHOLMOD_DOUBLE;
    a.sorted = 1;  // Eigen keeps row indices sorted within each column
    a.packed = matrix.isCompressed() ? 1 : 0;
    return a;
  }

  void remember_pattern(const SparseMatrix& matrix) {
    column_starts.assign(1, 0);
    pattern_rows.clear();
    for (Eigen::Index j = 0; j < matrix.outerSize(); ++j) {
      for (SparseMatrix::InnerIterator it(matrix, j); it; ++it) pattern_rows.push_back(it.index());
      column_starts.push_back(static_cast<int>(pattern_rows.size()));
    }
  }

  bool has_pattern(const SparseMatrix& matrix) const {
    if (matrix.outerSize() + 1 != static_cast<Eigen::Index>(column_starts.size())) return false;
    for (Eigen::Index j = 0; j < matrix.outerSize(); ++j) {
      int k = column_starts[static_cast<std::size_t>(j)];
      for (SparseMatrix::InnerIterator it(matrix, j); it; ++it, ++k) {
        if (k == column_starts[static_cast<std::size_t>(j) + 1] ||
            pattern_rows[static_cast<std::size_t>(k)] != it.index()) {
          return false;
        }
      }
      if (k != column_starts[static_cast<std::size_t>(j) + 1]) return false;
    }
    return true;
  }

  void analyze(const SparseMatrix& pattern) {
    if (pattern.rows() != pattern.cols()) {
      throw Error("cannot factorize a " + std::to_string(pattern.rows()) + "×" +
                  std::to_string(pattern.cols()) + " matrix: it is not square");
    }
    cholmod_free_factor(&factor, &common);
    factorized = false;
    size = 0;
    cholmod_sparse a = view(pattern);
    detail::thread_limited([&]() noexcept { factor = cholmod_analyze(&a, &common); });
    throw_if_failed(common, "analysis");
    size = pattern.rows();
    remember_pattern(pattern);
  }

  // Numeric factorization (analyzing first if needed); the reason it failed, or nothing.
  std::optional<std::string> factorize(const SparseMatrix& matrix) {
    if (!factor) {
      analyze(matrix);
    } else if (matrix.rows() != size || matrix.cols() != size || !has_pattern(matrix)) {
      throw Error("matrix (" + std::to_string(matrix.rows()) + "×" + std::to_string(matrix.cols()) +
                  ", " + std::to_string(matrix.nonZeros()) +
                  " entries) does not have the analyzed pattern (" + std::to_string(size) + "×" +
                  std::to_string(size) + ", " + std::to_string(pattern_rows.size()) + " entries)");
    }
    factorized = false;
    cholmod_sparse a = view(matrix);
    detail::thread_limited([&]() noexcept { cholmod_factorize(&a, factor, &common); });
    throw_if_failed(common, "factorization");
    if (common.status == CHOLMOD_NOT_POSDEF) {
      // L->minor is the failing column of the permuted matrix; Perm maps it back.
      const auto minor = static_cast<int>(factor->minor);
      const int column = factor->Perm ? static_cast<const int*>(factor->Perm)[minor] : minor;
      return kind == Kind::llt
                 ? "matrix is not positive definite (column " + std::to_string(column) + ")"
                 : "matrix is singular (zero pivot in column " + std::to_string(column) + ")";
    }
    const double rcond = cholmod_rcond(factor, &common);
    if (!(rcond > singular_rcond(size))) {  // also catches NaN from non-finite entries
      std::ostringstream message;
      message << "matrix is numerically singular (reciprocal condition estimate " << rcond << ")";
      return message.str();
    }
    factorized = true;
    return std::nullopt;
  }

  // A⁻¹ B (or another of CHOLMOD's systems, e.g. CHOLMOD_L) for the rows×columns column-major
  // matrix B at `b`; the result lives in `solution` until the next solve.
  Eigen::Map<const Eigen::MatrixXd> solve(const double* b, Eigen::Index rows, Eigen::Index columns,
                                          int system = CHOLMOD_A) {
    if (!factorized) throw Error("no factorization to solve with: factorize() first");
    if (rows != size) {
      throw Error("right-hand side has " + std::to_string(rows) + " rows, the matrix " +
                  std::to_string(size));
    }
    if (columns == 0) return {nullptr, size, 0};
    cholmod_dense rhs{};
    rhs.nrow = static_cast<std::size_t>(size);
    rhs.ncol = static_cast<std::size_t>(columns);
    rhs.nzmax = rhs.nrow * rhs.ncol;
    rhs.d = rhs.nrow;
    rhs.x = const_cast<double*>(b);  // read only, like the sparse views
    rhs.xtype = CHOLMOD_REAL;
    rhs.dtype = CHOLMOD_DOUBLE;
    detail::thread_limited([&]() noexcept {
      cholmod_solve2(system, factor, &rhs, nullptr, &solution, nullptr, &workspace_y, &workspace_e,
                     &common);
    });
    throw_if_failed(common, "solve");
    return {static_cast<const double*>(solution->x), size, columns};
  }

  Kind kind;
  cholmod_common common;
  cholmod_factor* factor = nullptr;  ///< Symbolic after analyze(), numeric after factorize().
  bool factorized = false;
  Eigen::Index size = 0;
  // The analyzed pattern (compressed columns), to reject a matrix it does not fit.
  std::vector<int> column_starts;
  std::vector<int> pattern_rows;
  // cholmod_solve2 reuses these between calls instead of allocating per solve.
  cholmod_dense* solution = nullptr;
  cholmod_dense* workspace_y = nullptr;
  cholmod_dense* workspace_e = nullptr;
};

SparseCholesky::SparseCholesky(Kind kind) : m_data(std::make_unique<Data>(kind)) {}
SparseCholesky::~SparseCholesky() = default;
SparseCholesky::SparseCholesky(SparseCholesky&&) noexcept = default;
SparseCholesky& SparseCholesky::operator=(SparseCholesky&&) noexcept = default;

void SparseCholesky::analyze(const SparseMatrix& pattern) { m_data->analyze(pattern); }

void SparseCholesky::factorize(const SparseMatrix& matrix) {
  if (const auto failure = m_data->factorize(matrix)) throw SolverError(*failure);
}

bool SparseCholesky::try_factorize(const SparseMatrix& matrix) {
  return !m_data->factorize(matrix).has_value();
}

bool SparseCholesky::factorized() const noexcept { return m_data->factorized; }

Eigen::VectorXd SparseCholesky::solve(const Eigen::VectorXd& b) const {
  return m_data->solve(b.data(), b.rows(), 1).col(0);
}

Eigen::MatrixXd SparseCholesky::solve(const Eigen::MatrixXd& b) const {
  return m_data->solve(b.data(), b.rows(), b.cols());
}

Eigen::MatrixXd SparseCholesky::solve_lower(const Eigen::MatrixXd& b) const {
  if (m_data->kind != Kind::llt) throw Error("solve_lower needs an llt factorization");
  const Eigen::MatrixXd permuted = m_data->solve(b.data(), b.rows(), b.cols(), CHOLMOD_P);
  return m_data->solve(permuted.data(), permuted.rows(), permuted.cols(), CHOLMOD_L);
}

Eigen::MatrixXd SparseCholesky::solve_upper(const Eigen::MatrixXd& b) const {
  if (m_data->kind != Kind::llt) throw Error("solve_upper needs an llt factorization");
  const Eigen::MatrixXd unpermuted = m_data->solve(b.data(), b.rows(), b.cols(), CHOLMOD_Lt);
  return m_data->solve(unpermuted.data(), unpermuted.rows(), unpermuted.cols(), CHOLMOD_Pt);
}

Eigen::Index SparseCholesky::rows() const noexcept { return m_data->size; }

SparseCholesky::Kind SparseCholesky::kind() const noexcept { return m_data->kind; }

}  // namespace khz::reduced
