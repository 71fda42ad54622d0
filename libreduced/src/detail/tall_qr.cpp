#include "tall_qr.hpp"

#include "thread_limited_call.hpp"

#include <khz/reduced/errors.hpp>

#include <string>
#include <vector>

// LAPACK's Fortran interface (Debian: liblapack.so.3, provided by OpenBLAS or the reference
// implementation), 32-bit integers.
extern "C" {
void dgeqrf_(const int* m, const int* n, double* a, const int* lda, double* tau, double* work,
             const int* lwork, int* info);
void dormqr_(const char* side, const char* trans, const int* m, const int* n, const int* k,
             const double* a, const int* lda, const double* tau, double* c, const int* ldc,
             double* work, const int* lwork, int* info);
}

namespace khz::reduced::detail {

namespace {

int lapack_size(Eigen::Index size) {
  if (size > Eigen::Index{2147483647}) throw Error("matrix too large for LAPACK (32-bit sizes)");
  return static_cast<int>(size);
}

void check(int info, const char* routine) {
  if (info != 0)
    throw Error(std::string(routine) + " failed (info = " + std::to_string(info) + ")");
}

}  // namespace

TallQr::TallQr(Eigen::MatrixXd matrix) : m_factors(std::move(matrix)) {
  const int m = lapack_size(m_factors.rows());
  const int n = lapack_size(m_factors.cols());
  if (m < n) throw Error("TallQr: the matrix is wider than tall");
  m_tau.resize(n);
  if (n == 0) return;
  int info = 0;
  int query = -1;
  double optimal = 0.0;
  dgeqrf_(&m, &n, m_factors.data(), &m, m_tau.data(), &optimal, &query, &info);
  check(info, "dgeqrf");
  const int lwork = static_cast<int>(optimal);
  std::vector<double> work(static_cast<std::size_t>(lwork));
  thread_limited([&]() noexcept {  // OpenBLAS's LAPACK runs threads
    dgeqrf_(&m, &n, m_factors.data(), &m, m_tau.data(), work.data(), &lwork, &info);
  });
  check(info, "dgeqrf");
}

Eigen::MatrixXd TallQr::r() const {
  const Eigen::Index n = m_factors.cols();
  return m_factors.topRows(n).triangularView<Eigen::Upper>();
}

void TallQr::apply_q(Eigen::MatrixXd& x) const {
  if (x.rows() != m_factors.rows()) throw Error("TallQr::apply_q: row count mismatch");
  const int m = lapack_size(x.rows());
  const int columns = lapack_size(x.cols());
  const int k = lapack_size(m_factors.cols());
  if (columns == 0 || k == 0) return;
  int info = 0;
  int query = -1;
  double optimal = 0.0;
  dormqr_("L", "N", &m, &columns, &k, m_factors.data(), &m, m_tau.data(), x.data(), &m, &optimal,
          &query, &info);
  check(info, "dormqr");
  const int lwork = static_cast<int>(optimal);
  std::vector<double> work(static_cast<std::size_t>(lwork));
  thread_limited([&]() noexcept {
    dormqr_("L", "N", &m, &columns, &k, m_factors.data(), &m, m_tau.data(), x.data(), &m,
            work.data(), &lwork, &info);
  });
  check(info, "dormqr");
}

}  // namespace khz::reduced::detail
