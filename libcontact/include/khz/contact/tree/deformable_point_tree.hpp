#pragma once
// A nested point tree over a reduced deformable pointshell: the tree's spheres become a
// point-based BD-tree (thesis §3.7, eq. 3.12; James & Pai 2004) and its points deform with the
// reduced coordinates q (§3.6, eq. 3.6 and 3.8).

#include <khz/contact/common.hpp>
#include <khz/contact/export.hpp>
#include <khz/contact/tree/point_tree.hpp>
#include <khz/reduced/fem/embedding.hpp>

#include <Eigen/Core>

#include <cassert>
#include <vector>

namespace khz::contact {

/// A PointTree whose points follow a reduced deformation u = Uq of a volume mesh they are
/// embedded in, with bounding-sphere radii that stay valid under it:
///   p_s(q) = P_s + U_s q                                    (eq. 3.6)
///   n_s(q) = n'_s / ‖n'_s‖,  n'_s = N_s + ΔN_s q             (eq. 3.8)
///   R_i(q) = R_i0 + Σ_j a_ij |q_j|                          (eq. 3.12)
/// R_i(q) bounds ‖p_s(q) − p_c(q)‖ for every point s in the subtree of node i, c its centre
/// point, for every q — not only small ones (derivation in deformable_point_tree.cpp; up to
/// rounding, ~1e-16 relative).
///
/// Layout, all in the traversal order of tree(): per point, U_s and ΔN_s are 3×r row-major
/// blocks (3r contiguous doubles, rows x, y, z) in two separate arrays (a traversal needs U_s
/// for every visited point, ΔN_s only for the few in contact, §3.6.2); per non-leaf node the r
/// coefficients a_i· are contiguous. Leaves store no coefficients (their radius is 0). A
/// traversal of node i reads tree().node(i) (point, children, R_i0), then position(point, q)
/// and bounding_radius(i, |q|): ~3r + r flops.
///
/// Immutable after construction; the const queries are noexcept, allocation-free and
/// thread-safe, and assert their preconditions in debug builds only.
class KHZ_CONTACT_API DeformablePointTree {
 public:
  /// ‖n'_s‖ below which normal() keeps the rest normal N_s (F_s(q) has collapsed it to rounding
  /// noise), as reduced::EmbeddedSurface::normal() does.
  static constexpr double min_normal_length = 1e-12;

  /// A point's 3×r block of modes (U_s or ΔN_s), viewed in place.
  using ModesView = Eigen::Map<const Eigen::Matrix<double, 3, Eigen::Dynamic, Eigen::RowMajor>>;

  /// Samples U_s and ΔN_s at the tree's points with reduced::EmbeddedSurface (FEM shape
  /// functions and deformation-gradient modes, §3.6.1–3.6.2; points outside the volume mesh
  /// extrapolate the nearest element), then computes the BD-tree coefficients. In parallel.
  /// @param embedding The volume mesh the basis lives on (n vertices); used only here.
  /// @param basis U, 3n×r (m per unit q), r ≥ 1.
  /// @param progress Reports stages "embedding points" and "BD-tree coefficients".
  /// @throws Error if `basis` does not have 3n rows or r < 1; Cancelled.
  DeformablePointTree(PointTree tree, const reduced::MeshEmbedding& embedding,
                      const Eigen::MatrixXd& basis, const ProgressCallback& progress = {});

  /// From modes sampled elsewhere (or loaded), in tree().pointshell() point order: point s's
  /// U_s (ΔN_s) is entries [3rs, 3r(s+1)) of `displacement_modes` (`normal_modes`), row-major
  /// 3×r. Computes the BD-tree coefficients (in parallel).
  /// @param dimension r ≥ 1.
  /// @throws Error if r < 1, an array does not have 3r × #points entries, or an entry is not
  ///         finite; Cancelled.
  DeformablePointTree(PointTree tree, Eigen::Index dimension,
                      std::vector<double> displacement_modes, std::vector<double> normal_modes,
                      const ProgressCallback& progress = {});

  /// The topology, rest positions and normals, rest radii R_i0.
  const PointTree& tree() const noexcept { return m_tree; }
  /// r, the number of reduced coordinates.
  Eigen::Index dimension() const noexcept { return m_dimension; }

  /// U_s (3×r, m per unit q).
  ModesView displacement_modes(Eigen::Index s) const noexcept {
    return ModesView(m_displacement_modes.data() + 3 * m_dimension * s, 3, m_dimension);
  }
  /// ΔN_s (3×r, per unit q): column j is F_{s,j} N_s.
  ModesView normal_modes(Eigen::Index s) const noexcept {
    return ModesView(m_normal_modes.data() + 3 * m_dimension * s, 3, m_dimension);
  }
  /// a_i· (r entries, m per unit q) of a non-leaf node, 0 ≤ node < tree().num_internal_nodes().
  Eigen::Map<const Eigen::VectorXd> radius_coefficients(Eigen::Index node) const noexcept {
    assert(node >= 0 && node < m_tree.num_internal_nodes());
    return {m_radius_coefficients.data() + m_dimension * node, m_dimension};
  }

  /// p_s(q) = P_s + U_s q (eq. 3.6, m) in 3r flops, inline (the traversal's inner loop).
  /// Preconditions: 0 ≤ s < number of points, q has r entries.
  Eigen::Vector3d position(Eigen::Index s,
                           const Eigen::Ref<const Eigen::VectorXd>& q) const noexcept {
    assert(s >= 0 && s < m_tree.num_points() && q.size() == m_dimension);
    return apply_modes(m_displacement_modes.data() + 3 * m_dimension * s, q.data(),
                       m_tree.pointshell().points.data() + 3 * s);
  }
  /// n_s(q) (eq. 3.8): the unit inward normal pushed forward by the deformation gradient, in 3r
  /// flops and a normalization; N_s where ‖n'_s‖ < min_normal_length (as
  /// reduced::EmbeddedSurface::normal). A non-finite q gives a non-finite normal. Preconditions
  /// as for position().
  Eigen::Vector3d normal(Eigen::Index s,
                         const Eigen::Ref<const Eigen::VectorXd>& q) const noexcept {
    assert(s >= 0 && s < m_tree.num_points() && q.size() == m_dimension);
    const double* rest = m_tree.pointshell().normals.data() + 3 * s;
    const Eigen::Vector3d pushed =
        apply_modes(m_normal_modes.data() + 3 * m_dimension * s, q.data(), rest);
    const double length = pushed.norm();
    return length < min_normal_length ? Eigen::Vector3d(rest[0], rest[1], rest[2])
                                      : Eigen::Vector3d(pushed / length);
  }
  /// max_s ‖U_s‖_F (m per unit q): no point moves more than this times ‖Δq‖ when q changes by
  /// Δq (‖U_s Δq‖ ≤ ‖U_s‖_F ‖Δq‖). Temporal coherence bounds deformation with it (§3.10.2).
  double displacement_bound() const noexcept { return m_displacement_bound; }
  /// R_i(q) = R_i0 + Σ_j a_ij |q_j| (eq. 3.12, m) in r flops; 0 for a leaf. Takes |q| (r
  /// entries, each ≥ 0), computed once per haptic cycle rather than once per node.
  double bounding_radius(Eigen::Index node,
                         const Eigen::Ref<const Eigen::VectorXd>& abs_q) const noexcept;

 private:
  void compute_radius_coefficients(const ProgressCallback& progress);
  void compute_displacement_bound() noexcept;

  /// rest + M q for a point's row-major 3×r block M: one pass over q serves the three rows, in
  /// four independent partial sums per row (floating-point addition does not reassociate, so
  /// the compiler would otherwise chain every product through one register).
  Eigen::Vector3d apply_modes(const double* modes, const double* q,
                              const double* rest) const noexcept {
    constexpr int lanes = 4;
    const double* x = modes;
    const double* y = x + m_dimension;
    const double* z = y + m_dimension;
    double sx[lanes] = {}, sy[lanes] = {}, sz[lanes] = {};
    Eigen::Index j = 0;
    for (; j + lanes <= m_dimension; j += lanes) {
      for (int l = 0; l < lanes; ++l) {
        sx[l] += x[j + l] * q[j + l];
        sy[l] += y[j + l] * q[j + l];
        sz[l] += z[j + l] * q[j + l];
      }
    }
    for (int l = 0; j < m_dimension; ++j, ++l) {
      sx[l] += x[j] * q[j];
      sy[l] += y[j] * q[j];
      sz[l] += z[j] * q[j];
    }
    return {rest[0] + ((sx[0] + sx[1]) + (sx[2] + sx[3])),
            rest[1] + ((sy[0] + sy[1]) + (sy[2] + sy[3])),
            rest[2] + ((sz[0] + sz[1]) + (sz[2] + sz[3]))};
  }

  PointTree m_tree;
  Eigen::Index m_dimension = 0;
  std::vector<double> m_displacement_modes;   // #points × 3r
  std::vector<double> m_normal_modes;         // #points × 3r
  std::vector<double> m_radius_coefficients;  // num_internal_nodes × r
  double m_displacement_bound = 0.0;
};

}  // namespace khz::contact
