#pragma once
// The full (unreduced) nonlinear FEM model: mass, internal forces, tangent stiffness, energy.

#include <khz/reduced/export.hpp>
#include <khz/reduced/fem/material.hpp>
#include <khz/reduced/mesh/volume_mesh.hpp>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include <memory>
#include <vector>

namespace khz::reduced {

/// Sparse matrices of the full model: 3n×3n, column-major, dof 3v+i is vertex v's axis i.
using SparseMatrix = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;

/// How the mass matrix distributes each element's mass.
enum class MassLumping {
  consistent,  ///< ∫ρ φ_a φ_b dV I₃ (thesis eq. 2.49).
  lumped,      ///< Row sums of the consistent matrix on the diagonal.
};

/// A geometrically nonlinear FEM model of a volume mesh with linear materials (StVK or general
/// anisotropic, thesis §2.1.4, §2.1.8), immutable after construction and safe to share between
/// threads. Displacement vectors u have 3n entries (metres); forces are in newtons.
///
/// Construction precomputes, per element and quadrature point (1 for tetrahedra, 2×2×2 Gauss
/// for hexahedra), the rest-shape gradients ∇φ_a and the integration weights, and the fixed
/// sparsity pattern of K. Fixed vertices are not part of the model: solvers remove their dofs.
///
/// Element loops run in parallel with OpenMP (set the thread count with OMP_NUM_THREADS or
/// omp_set_num_threads). R, K and the Hessian contraction are bit-identical for any thread count;
/// the strain energy, a parallel sum, agrees to round-off. Every evaluation @throws Error if a
/// vector does not have num_dofs() entries.
class KHZ_REDUCED_API FemModel {
 public:
  /// @param mesh      the rest shape; every element must have positive volume (tetrahedra) or
  ///                  a positive Jacobian at every quadrature point (hexahedra).
  /// @param materials materials indexed by mesh.element_groups (group g uses materials[g]); a
  ///                  mesh without groups uses materials[0] everywhere.
  /// @throws MeshError naming the first inverted or degenerate element; Error if a group has no
  ///         material or `materials` is empty.
  FemModel(VolumeMesh mesh, std::vector<Material> materials);
  ~FemModel();
  FemModel(FemModel&&) noexcept;
  FemModel& operator=(FemModel&&) noexcept;

  const VolumeMesh& mesh() const noexcept;
  const std::vector<Material>& materials() const noexcept;
  /// Material of element e.
  const Material& element_material(Eigen::Index element) const noexcept;
  /// 3 × number of vertices.
  Eigen::Index num_dofs() const noexcept;

  /// Quadrature points per element: 1 (tetrahedra) or 8 (hexahedra).
  int quadrature_points_per_element() const noexcept;
  /// Rest-shape gradients ∇φ_a (row a, 1/m) of element e's shape functions at quadrature point
  /// q, nodes_per_element × 3. Later layers (reduced polynomials) integrate with these.
  Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>> shape_gradients(
      Eigen::Index element, int q) const noexcept;
  /// Integration weight of element e's quadrature point q (m³); they sum to the element volume.
  double quadrature_weight(Eigen::Index element, int q) const noexcept;

  /// Mass matrix (kg), 3n×3n.
  SparseMatrix mass_matrix(MassLumping lumping = MassLumping::consistent) const;
  /// The mass matrix of material group g's elements alone at unit density (m³, i.e. kg per
  /// kg/m³): mass_matrix() = Σ_g ρ_g · unit_density_mass_matrix(g), which lets reduced models
  /// change densities at runtime (thesis §2.11). @throws Error if g is not a group index.
  SparseMatrix unit_density_mass_matrix(int group,
                                        MassLumping lumping = MassLumping::consistent) const;

  /// Strain energy ∫ ½ E:C:E dV (J) of displacement u.
  double strain_energy(const Eigen::VectorXd& u) const;
  /// Internal forces R(u) = ∂energy/∂u (N), written into `forces` (resized to 3n).
  void internal_forces(const Eigen::VectorXd& u, Eigen::VectorXd& forces) const;
  /// An all-zero matrix with the sparsity pattern of K(u), to pass to the functions below.
  SparseMatrix stiffness_pattern() const;
  /// Tangent stiffness K(u) = ∂R/∂u (N/m) assembled in place into `stiffness`, which must have
  /// stiffness_pattern()'s pattern: no allocation. @throws Error if it has not (size and entry
  /// count are always checked, the index arrays in debug builds).
  void tangent_stiffness(const Eigen::VectorXd& u, SparseMatrix& stiffness) const;
  /// R(u) and K(u) in one pass over the elements (what Newton solvers need).
  void forces_and_stiffness(const Eigen::VectorXd& u, Eigen::VectorXd& forces,
                            SparseMatrix& stiffness) const;
  /// The Hessian contraction (H : v) = d/dε K(εv) at ε = 0 (thesis eq. 2.48–2.50), used for modal
  /// derivatives (eq. 2.47); same pattern as K.
  SparseMatrix hessian_contraction(const Eigen::VectorXd& v) const;

 private:
  struct Data;
  std::unique_ptr<Data> m_data;
};

}  // namespace khz::reduced
