#include <khz/reduced/errors.hpp>
#include <khz/reduced/subspace/embedded_surface.hpp>
#include <khz/reduced/subspace/vertex_normals.hpp>
#include <khz/reduced/worker_threads.hpp>

#include "detail/size_check.hpp"

#include <cassert>
#include <string>

namespace khz::reduced {

namespace {

// Bulk calls run on one thread below this many mode entries (points × r). Measured on 2 Xeon
// cores, release build, r = 30: one thread wins up to ~4k entries (≈ 1 µs of work, the cost of
// the parallel region); at 8k two threads take 0.75× the time, at 30k 0.57×. Far beyond the
// caches the loop is bound by memory bandwidth (72 MB per call for 100k points at r = 30), which
// one thread already saturated on that machine.
// (Read only by OpenMP's if clauses: unused in a build without OpenMP.)
[[maybe_unused]] constexpr Eigen::Index min_parallel_entries = 1 << 13;
// ‖n'_s‖ below this (dimensionless: N_s is unit) means F_s(q) has collapsed the normal direction
// to rounding noise; the rest normal is kept (eq. 3.8 has no meaningful direction there).
constexpr double min_normal_length = 1e-12;

// rest + M q for one point's 3×r row-major block M at `modes` (eq. 3.6 / 3.8): the three rows'
// dot products with q, accumulated together four columns at a time so each load of q serves all
// three (measured 1.7× faster than three Eigen dot() calls at r = 30). position(), normal() and
// the bulk loops all run this, so they give the same bits.
inline Eigen::Vector3d apply_modes(const double* modes, Eigen::Index r,
                                   const Eigen::Ref<const Eigen::VectorXd>& q,
                                   const Eigen::Vector3d& rest) {
  using Lanes = Eigen::Array4d;
  using LanesMap = Eigen::Map<const Lanes>;
  const double* x = modes;
  const double* y = modes + r;
  const double* z = modes + 2 * r;
  Lanes sum_x = Lanes::Zero();
  Lanes sum_y = Lanes::Zero();
  Lanes sum_z = Lanes::Zero();
  Eigen::Index j = 0;
  for (; j + 4 <= r; j += 4) {
    const Lanes qj = LanesMap(q.data() + j);
    sum_x += LanesMap(x + j) * qj;
    sum_y += LanesMap(y + j) * qj;
    sum_z += LanesMap(z + j) * qj;
  }
  Eigen::Vector3d result(sum_x.sum(), sum_y.sum(), sum_z.sum());
  for (; j < r; ++j) {
    result[0] += x[j] * q[j];
    result[1] += y[j] * q[j];
    result[2] += z[j] * q[j];
  }
  return result + rest;
}

inline Eigen::Vector3d normalized_or_rest(const Eigen::Vector3d& pushed,
                                          const Eigen::Vector3d& rest) {
  const double length = pushed.norm();
  // NaN compares false: a non-finite q propagates rather than silently returning N_s.
  return length < min_normal_length ? rest : Eigen::Vector3d(pushed / length);
}

VertexMatrix surface_normals(const TriangleMesh& surface) {
  validate(surface);
  VertexMatrix normals(surface.num_vertices(), 3);
  vertex_normals(surface.vertices, surface.triangles, normals);
  return normals;
}

void check_finite_normals(const Eigen::Ref<const VertexMatrix>& normals) {
  for (Eigen::Index s = 0; s < normals.rows(); ++s) {
    if (!normals.row(s).allFinite()) {
      throw Error("normal " + std::to_string(s) + " has a non-finite component");
    }
  }
}

}  // namespace

EmbeddedSurface::EmbeddedSurface(const MeshEmbedding& embedding, const TriangleMesh& surface,
                                 const Eigen::MatrixXd& basis)
    : EmbeddedSurface(embedding, surface.vertices, surface_normals(surface), basis) {}

EmbeddedSurface::EmbeddedSurface(const MeshEmbedding& embedding,
                                 const Eigen::Ref<const VertexMatrix>& points,
                                 const Eigen::Ref<const VertexMatrix>& normals,
                                 const Eigen::MatrixXd& basis)
    : m_dimension(basis.cols()), m_rest_positions(points), m_rest_normals(normals) {
  // Everything that can throw is checked before the parallel loop: an exception must not leave
  // an OpenMP region.
  detail::check_size("basis", "rows", basis.rows(), 3 * embedding.mesh().num_vertices(),
                     "three per volume-mesh vertex");
  detail::check_size("normals", "rows", normals.rows(), points.rows(), "one per point");
  check_finite_normals(normals);
  m_embedded = embedding.locate_all(points);  // throws naming a non-finite point

  const Eigen::Index count = size();
  const Eigen::Index r = m_dimension;
  m_displacement_modes.resize(static_cast<std::size_t>(3 * count * r));
  m_normal_modes.resize(static_cast<std::size_t>(3 * count * r));
  // Thesis eq. 3.6: U_s = Σ_a φ_a(X) U_a; eq. 3.7–3.8: column j of ΔN_s is F_{s,j} N_s =
  // Σ_a U_{a,j} (∇φ_a · N_s). Both are sums of the element's node blocks U_a (3×r), weighted by
  // φ_a and by ∇φ_a · N_s. U_s sums in the order MeshEmbedding::modes() does and gives its bits.
  // (A row-major copy of the basis, each block then contiguous, was 25% faster on the demo's
  // dragon, but costs a copy of the whole basis per call: more than it saves for large models.)
  using Block = Eigen::Map<Eigen::Matrix<double, 3, Eigen::Dynamic, Eigen::RowMajor>>;
  const VolumeMesh& mesh = embedding.mesh();
  const Eigen::Index nodes_per_element = mesh.elements.cols();
#pragma omp parallel for num_threads(worker_threads()) schedule(dynamic, 256)
  for (Eigen::Index s = 0; s < count; ++s) {
    const double length = m_rest_normals.row(s).norm();
    if (length > 0.0) m_rest_normals.row(s) /= length;
    const Eigen::Vector3d normal = m_rest_normals.row(s).transpose();
    const EmbeddedPoint& point = m_embedded[static_cast<std::size_t>(s)];
    Block displacement(m_displacement_modes.data() + 3 * s * r, 3, r);
    Block pushed(m_normal_modes.data() + 3 * s * r, 3, r);
    displacement.setZero();
    pushed.setZero();
    for (Eigen::Index a = 0; a < nodes_per_element; ++a) {
      const auto node_rows = basis.middleRows<3>(3 * mesh.elements(point.element, a));
      displacement += point.weights[a] * node_rows;
      pushed += point.gradients.row(a).dot(normal.transpose()) * node_rows;
    }
  }
}

void EmbeddedSurface::deformed_positions(const Eigen::Ref<const Eigen::VectorXd>& q,
                                         Eigen::Ref<VertexMatrix> positions) const {
  detail::check_size("q", "entries", q.size(), m_dimension, "one per basis column");
  detail::check_size("positions", "rows", positions.rows(), size(), "one per point");
  const Eigen::Index count = size();
#pragma omp parallel for num_threads(worker_threads()) \
    schedule(static) if (count * m_dimension >= min_parallel_entries)
  for (Eigen::Index s = 0; s < count; ++s) {
    const Eigen::Vector3d p = position(s, q);
    for (int k = 0; k < 3; ++k) positions(s, k) = p[k];
  }
}

void EmbeddedSurface::deformed_normals(const Eigen::Ref<const Eigen::VectorXd>& q,
                                       Eigen::Ref<VertexMatrix> normals) const {
  detail::check_size("q", "entries", q.size(), m_dimension, "one per basis column");
  detail::check_size("normals", "rows", normals.rows(), size(), "one per point");
  const Eigen::Index count = size();
#pragma omp parallel for num_threads(worker_threads()) \
    schedule(static) if (count * m_dimension >= min_parallel_entries)
  for (Eigen::Index s = 0; s < count; ++s) {
    const Eigen::Vector3d n = normal(s, q);
    for (int k = 0; k < 3; ++k) normals(s, k) = n[k];
  }
}

Eigen::Vector3d EmbeddedSurface::position(
    Eigen::Index s, const Eigen::Ref<const Eigen::VectorXd>& q) const noexcept {
  assert(s >= 0 && s < size() && q.size() == m_dimension);
  return apply_modes(m_displacement_modes.data() + 3 * s * m_dimension, m_dimension, q,
                     m_rest_positions.row(s).transpose());
}

Eigen::Vector3d EmbeddedSurface::normal(Eigen::Index s,
                                        const Eigen::Ref<const Eigen::VectorXd>& q) const noexcept {
  assert(s >= 0 && s < size() && q.size() == m_dimension);
  const Eigen::Vector3d rest = m_rest_normals.row(s).transpose();
  return normalized_or_rest(
      apply_modes(m_normal_modes.data() + 3 * s * m_dimension, m_dimension, q, rest), rest);
}

}  // namespace khz::reduced
