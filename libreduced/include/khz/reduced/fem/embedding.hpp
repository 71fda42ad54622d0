#pragma once
// Embedding points in a volume mesh: how render-mesh vertices and pointshell points follow the
// simulation (thesis §2.5.2, §3.6). This is the narrow interface libcontact builds on.

#include <khz/reduced/export.hpp>
#include <khz/reduced/mesh/volume_mesh.hpp>

#include <Eigen/Core>

#include <memory>
#include <vector>

namespace khz::reduced {

/// Where a rest-shape point sits in the volume mesh.
///
/// Contract: the point's displacement is Σ_a weights[a] · u(node a) over the element's nodes
/// (4 for tetrahedra, 8 for hexahedra; unused weights are zero), and its deformation gradient
/// is I + Σ_a u(node a) ⊗ gradients.row(a). Points outside the mesh are attached to the nearest
/// element and extrapolate its field (the weights then leave [0, 1]).
struct EmbeddedPoint {
  Eigen::Index element = -1;  ///< Containing (or nearest) element.
  Eigen::Matrix<double, 8, 1> weights = Eigen::Matrix<double, 8, 1>::Zero();  ///< Shape values.
  /// ∇φ_a at the point (row a, 1/m), in rest coordinates.
  Eigen::Matrix<double, 8, 3, Eigen::RowMajor> gradients =
      Eigen::Matrix<double, 8, 3, Eigen::RowMajor>::Zero();
  /// 0 inside; otherwise the distance (m) from the point to the element it was attached to.
  double distance_outside = 0.0;
};

/// A point's view of a basis U (3n×r): its displacement modes and deformation-gradient modes,
/// so that u(X) = U_s q and F(X) = I + Σ_j q_j F_j (thesis eq. 3.6–3.7).
struct PointModes {
  Eigen::Matrix<double, 3, Eigen::Dynamic> displacement;  ///< U_s, 3×r.
  std::vector<Eigen::Matrix3d> gradient;                  ///< F_{s,j}, r matrices 3×3.
};

/// Locates points in a volume mesh with a bounding-volume hierarchy over the elements.
/// Immutable after construction; queries are thread-safe.
///
/// A point is inside an element when its barycentric coordinates (tetrahedra) are ≥ −1e-12 or
/// its natural coordinates (hexahedra) lie in [−1−1e-12, 1+1e-12]³. A point on a face, edge or
/// vertex shared by several elements goes to the one it is deepest inside, the lowest index on
/// ties, so the result depends only on the mesh and the point.
class KHZ_REDUCED_API MeshEmbedding {
 public:
  /// Copies the mesh and builds the hierarchy (O(E log E)).
  /// @throws MeshError if the mesh fails validate(), has no elements, or has an element with no
  ///         interior (a tetrahedron with volume ≤ 0, a hexahedron with Jacobian ≤ 0 at a Gauss
  ///         point; FemModel rejects these too), naming that element.
  explicit MeshEmbedding(const VolumeMesh& mesh);
  ~MeshEmbedding();
  MeshEmbedding(MeshEmbedding&&) noexcept;
  MeshEmbedding& operator=(MeshEmbedding&&) noexcept;

  /// Embeds rest-shape point `x` (m): the element containing it, or else the element nearest
  /// to it (true distance to the element's boundary; a hexahedron's faces count as two
  /// triangles each), whose field is extrapolated: barycentric coordinates for tetrahedra,
  /// natural coordinates for hexahedra — or, if Newton finds none, those of the nearest point
  /// on the element's boundary.
  /// @throws Error if `x` has a non-finite coordinate.
  EmbeddedPoint locate(const Eigen::Vector3d& x) const;
  /// Embeds every row of `points` (#P×3), in parallel (OpenMP); row p gives entry p, equal to
  /// locate(points.row(p)).
  /// @throws Error naming the first row with a non-finite coordinate.
  std::vector<EmbeddedPoint> locate_all(
      const Eigen::Ref<const Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>>& points)
      const;

  /// Displacement (m) of an embedded point under the full displacement u (3n).
  /// interpolate(), distribute_force() and modes() throw Error if a vector or basis does not
  /// have 3n rows or the point names no element of this mesh.
  Eigen::Vector3d interpolate(const EmbeddedPoint& point, const Eigen::VectorXd& u) const;
  /// Adds force f (N) acting at the point to the full force vector `forces` (3n), split over
  /// the element's nodes by the shape weights (the transpose of interpolate()).
  void distribute_force(const EmbeddedPoint& point, const Eigen::Vector3d& f,
                        Eigen::VectorXd& forces) const;
  /// The point's displacement and deformation-gradient modes for basis U (3n×r).
  PointModes modes(const EmbeddedPoint& point, const Eigen::MatrixXd& basis) const;

  const VolumeMesh& mesh() const noexcept;

 private:
  struct Data;
  std::unique_ptr<Data> m_data;
};

}  // namespace khz::reduced
