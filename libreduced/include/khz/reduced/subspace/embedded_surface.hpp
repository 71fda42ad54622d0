#pragma once
// Surface points with normals carried by the reduced deformation of a volume mesh: the vertices
// of a render mesh (thesis §2.12, "dynamic normals") or the points of a deformable pointshell
// (§3.6.1–3.6.2).

#include <khz/reduced/export.hpp>
#include <khz/reduced/fem/embedding.hpp>
#include <khz/reduced/mesh/triangle_mesh.hpp>

#include <Eigen/Core>

#include <vector>

namespace khz::reduced {

/// Surface points P_s with normals N_s, embedded in a simulation volume mesh and reduced onto a
/// basis U, so that for reduced coordinates q (thesis §3.6)
///   p_s = P_s + U_s q                           (eq. 3.6)
///   n_s = n'_s / ‖n'_s‖,  n'_s = N_s + ΔN_s q    (eq. 3.8)
/// where U_s (3×r, metres per unit q) interpolates U at P_s with the FEM shape functions and
/// column j of ΔN_s (3×r, per unit q) is F_{s,j} N_s, F_{s,j} the deformation-gradient modes of
/// eq. 3.7 (F_s(q) = I + Σ_j F_{s,j} q_j). Points outside the volume mesh extrapolate the field
/// of the nearest element (MeshEmbedding::locate()).
///
/// n_s pushes N_s forward by the deformation gradient, F N: exact under rotation and uniform
/// scaling (F = sR), approximate under shear or non-uniform stretch, where the true normal is
/// F⁻ᵀN normalized (vertex_normals() of the deformed mesh gives that). For the large-rotation,
/// small-strain deformations of reduced StVK models the thesis measures at most 5.2° (Fig. 3.7).
///
/// Immutable after construction; the const queries are thread-safe. Points are stored in the
/// order given, so give them in the order they will be read (libcontact: the pointshell's
/// traversal order, §3.9). Point indices s are not range-checked (position() and normal()
/// assert 0 ≤ s < size() in debug builds).
class KHZ_REDUCED_API EmbeddedSurface {
 public:
  /// A per-point 3×r block of modes (U_s or ΔN_s), viewed in place.
  using ModesView = Eigen::Map<const Eigen::Matrix<double, 3, Eigen::Dynamic, Eigen::RowMajor>>;

  /// Embeds the vertices of a render mesh, with normals computed by vertex_normals() (area
  /// weighted, outward for a closed mesh whose triangles are counter-clockwise seen from
  /// outside). A vertex in no triangle gets a zero normal, which stays zero (see normal()).
  /// In parallel (OpenMP).
  /// @param embedding The simulation volume mesh (n vertices), used only during construction.
  /// @param surface Rest-shape triangle mesh (metres); its triangles are not stored.
  /// @param basis U, 3n×r (metres per unit of q).
  /// @throws MeshError if `surface` fails validate(); Error if `basis` does not have 3n rows.
  EmbeddedSurface(const MeshEmbedding& embedding, const TriangleMesh& surface,
                  const Eigen::MatrixXd& basis);
  /// Embeds points with given normals (a pointshell's, or a render mesh's own), in parallel.
  /// Non-zero normals are normalized; zero normals stay zero. `embedding` and `basis` as above.
  /// @param points #S×3 rest positions P_s (metres).
  /// @param normals #S×3 rest normals N_s (any length; pointshell normals point inward, §3.5).
  /// @throws Error if `basis` does not have 3n rows, `normals` does not have #S rows, or a point
  ///         or normal has a non-finite coordinate (naming it).
  EmbeddedSurface(const MeshEmbedding& embedding, const Eigen::Ref<const VertexMatrix>& points,
                  const Eigen::Ref<const VertexMatrix>& normals, const Eigen::MatrixXd& basis);

  /// S, the number of points.
  Eigen::Index size() const noexcept { return m_rest_positions.rows(); }
  /// r, the number of reduced coordinates q.
  Eigen::Index dimension() const noexcept { return m_dimension; }

  /// All deformed positions p_s (eq. 3.6, metres) into the caller-presized `positions`
  /// (#S×3). Allocates nothing; parallel over points for large sets; each row equals
  /// position(s, q) bit for bit, for any number of threads.
  /// @throws Error if q does not have r entries or `positions` #S rows (checked first).
  void deformed_positions(const Eigen::Ref<const Eigen::VectorXd>& q,
                          Eigen::Ref<VertexMatrix> positions) const;
  /// All deformed unit normals n_s (eq. 3.8) into the caller-presized `normals` (#S×3), with the
  /// same threading, allocation and failure behaviour as deformed_positions(); each row equals
  /// normal(s, q) bit for bit.
  void deformed_normals(const Eigen::Ref<const Eigen::VectorXd>& q,
                        Eigen::Ref<VertexMatrix> normals) const;

  /// p_s = P_s + U_s q (eq. 3.6, metres) of point s alone, in 3r flops: for sparse queries such
  /// as pointshell points visited by a tree traversal. Preconditions (asserted in debug builds):
  /// 0 ≤ s < size(), q has r entries.
  Eigen::Vector3d position(Eigen::Index s,
                           const Eigen::Ref<const Eigen::VectorXd>& q) const noexcept;
  /// n_s = n'_s / ‖n'_s‖, n'_s = N_s + ΔN_s q (eq. 3.8) of point s alone, in 3r flops plus a
  /// normalization. Where ‖n'_s‖ < 1e-12 — F_s(q) collapses the normal direction to rounding
  /// noise, or N_s is zero — the rest normal N_s is returned instead. Non-finite q gives a
  /// non-finite normal. Preconditions as for position().
  Eigen::Vector3d normal(Eigen::Index s, const Eigen::Ref<const Eigen::VectorXd>& q) const noexcept;

  /// P_s, the rest position (metres).
  Eigen::Vector3d rest_position(Eigen::Index s) const { return m_rest_positions.row(s); }
  /// N_s, the rest normal: unit, or zero for a point without one.
  Eigen::Vector3d rest_normal(Eigen::Index s) const { return m_rest_normals.row(s); }
  /// Where P_s sits in the volume mesh.
  const EmbeddedPoint& embedded_point(Eigen::Index s) const {
    return m_embedded[static_cast<std::size_t>(s)];
  }
  /// U_s, 3×r (metres per unit q): the displacement modes at P_s (eq. 3.6). U_sᵀ f is the reduced
  /// force of a force f (N) acting at the point (§3.6.1).
  ModesView displacement_modes(Eigen::Index s) const {
    return ModesView(m_displacement_modes.data() + 3 * s * m_dimension, 3, m_dimension);
  }
  /// ΔN_s, 3×r (per unit q): column j is F_{s,j} N_s (eq. 3.8).
  ModesView normal_modes(Eigen::Index s) const {
    return ModesView(m_normal_modes.data() + 3 * s * m_dimension, 3, m_dimension);
  }

 private:
  Eigen::Index m_dimension = 0;
  VertexMatrix m_rest_positions;
  VertexMatrix m_rest_normals;
  std::vector<EmbeddedPoint> m_embedded;
  // U_s of every point in one array and ΔN_s in another, point after point: rows 3s … 3s+2 of
  // a row-major 3S×r array, so one point's modes are one contiguous block of 3r doubles and its
  // output is three dot products of contiguous rows with q. Two arrays rather than one
  // interleaved [U_s; ΔN_s] block per point because the two are read separately: a renderer
  // streams each array once per frame, and a contact query needs positions for every traversed
  // point but normals only for the few in contact (§3.6.2) — interleaving would drag the unused
  // half of each block through the cache.
  std::vector<double> m_displacement_modes;
  std::vector<double> m_normal_modes;
};

}  // namespace khz::reduced
