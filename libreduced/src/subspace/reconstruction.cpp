#include <khz/reduced/subspace/reconstruction.hpp>
#include <khz/reduced/worker_threads.hpp>

#include "detail/size_check.hpp"

#include <algorithm>

namespace khz::reduced {

namespace {

// Rows of U (256 vertices) per parallel chunk. Fixed, so each chunk is the same matrix-vector
// product for any thread count and the result is bit-identical on one thread or many.
constexpr Eigen::Index chunk_rows = 3 * 256;
// Below this many entries of U (rows × columns) one thread is as fast. Measured on 2 Xeon cores,
// release build, r = 30: no gain at 92k entries (6 µs), two threads take 0.7× the time at 184k.
// Far beyond the caches the product is bound by memory bandwidth, which one thread already
// saturated on that machine (U of 100k vertices, 75 MB: 9 ms on one thread or two).
constexpr Eigen::Index min_parallel_entries = 1 << 17;

// u += U q, in chunks of rows; `u` points at basis.rows() contiguous entries.
void add_basis_product(const Eigen::Ref<const Eigen::MatrixXd>& basis,
                       const Eigen::Ref<const Eigen::VectorXd>& q, double* u) {
  const Eigen::Index rows = basis.rows();
  const Eigen::Index chunks = (rows + chunk_rows - 1) / chunk_rows;
#pragma omp parallel for num_threads(worker_threads()) \
    schedule(static) if (rows * basis.cols() >= min_parallel_entries)
  for (Eigen::Index c = 0; c < chunks; ++c) {
    const Eigen::Index begin = c * chunk_rows;
    const Eigen::Index size = std::min(chunk_rows, rows - begin);
    Eigen::Map<Eigen::VectorXd>(u + begin, size).noalias() += basis.middleRows(begin, size) * q;
  }
}

}  // namespace

void reconstruct_displacement(const Eigen::Ref<const Eigen::MatrixXd>& basis,
                              const Eigen::Ref<const Eigen::VectorXd>& q,
                              Eigen::Ref<Eigen::VectorXd> displacement) {
  detail::check_size("q", "entries", q.size(), basis.cols(), "one per basis column");
  detail::check_size("displacement", "entries", displacement.size(), basis.rows(),
                     "one per basis row");
  displacement.setZero();
  add_basis_product(basis, q, displacement.data());
}

void reconstruct_positions(const Eigen::Ref<const VertexMatrix>& rest,
                           const Eigen::Ref<const Eigen::MatrixXd>& basis,
                           const Eigen::Ref<const Eigen::VectorXd>& q,
                           Eigen::Ref<VertexMatrix, 0, Eigen::OuterStride<3>> positions) {
  detail::check_size("basis", "rows", basis.rows(), 3 * rest.rows(), "three per rest vertex");
  detail::check_size("q", "entries", q.size(), basis.cols(), "one per basis column");
  detail::check_size("positions", "rows", positions.rows(), rest.rows(), "one per rest vertex");
  positions = rest;
  add_basis_product(basis, q, positions.data());
}

}  // namespace khz::reduced
