#pragma once
// Dirichlet boundary conditions by elimination: vertices held at zero displacement, whose dofs
// are removed from the systems the solvers see (thesis Fig. 2.6: the constrained vertices).

#include <khz/reduced/export.hpp>
#include <khz/reduced/fem/fem_model.hpp>
#include <khz/reduced/mesh/triangle_mesh.hpp>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <span>
#include <vector>

namespace khz::reduced {

/// Maps between the full dofs of a mesh (3 per vertex, dof 3v+i is vertex v's axis i) and the
/// free ones, i.e. those of vertices not fixed. Free dofs keep their relative order. Immutable
/// after construction.
class KHZ_REDUCED_API FixedDofs {
 public:
  /// @param num_vertices   vertices of the mesh (≥ 0).
  /// @param fixed_vertices indices of the vertices held at zero displacement; repeats allowed.
  /// @throws Error if num_vertices < 0 or an index lies outside [0, num_vertices), naming it.
  FixedDofs(Eigen::Index num_vertices, std::span<const int> fixed_vertices);

  /// 3 × the number of vertices.
  Eigen::Index num_full_dofs() const noexcept;
  /// Full dofs minus 3 × the number of distinct fixed vertices.
  Eigen::Index num_free_dofs() const noexcept;
  /// Whether vertex v is fixed (v in [0, num_vertices)).
  bool is_fixed(Eigen::Index vertex) const noexcept;

  /// The free entries of a full vector.
  /// @throws Error if `full` does not have num_full_dofs() entries.
  Eigen::VectorXd restrict_vector(const Eigen::VectorXd& full) const;
  /// Writes a free vector into `full` (resized to num_full_dofs()), fixed dofs set to 0.
  /// @throws Error if `free` does not have num_free_dofs() entries.
  void expand_vector(const Eigen::VectorXd& free, Eigen::VectorXd& full) const;

  /// The free rows of a num_full_dofs() × k matrix (e.g. a set of modes), in order.
  /// @throws Error if `full` does not have num_full_dofs() rows.
  Eigen::MatrixXd restrict_rows(const Eigen::MatrixXd& full) const;
  /// The num_full_dofs() × k matrix with `free`'s rows at the free dofs and zero rows at the
  /// fixed ones. @throws Error if `free` does not have num_free_dofs() rows.
  Eigen::MatrixXd expand_rows(const Eigen::MatrixXd& free) const;

  /// The rows and columns of the free dofs of a full num_full_dofs()² matrix, keeping every
  /// stored entry (explicit zeros too, so a stiffness pattern stays a pattern).
  /// @throws Error if `full` is not num_full_dofs() × num_full_dofs().
  SparseMatrix restrict_matrix(const SparseMatrix& full) const;
  /// Copies the values of `full` into `restricted`, a restrict_matrix() result of a matrix with
  /// the same pattern, without allocating: for refreshing a restricted tangent stiffness in a
  /// Newton loop.
  /// @throws Error if the patterns do not correspond (then `restricted` is partly updated).
  void restrict_matrix_values(const SparseMatrix& full, SparseMatrix& restricted) const;

 private:
  void check_full_matrix(const SparseMatrix& full) const;

  std::vector<int> m_full_to_free;  ///< Free index of each full dof, −1 for fixed dofs.
  std::vector<int> m_free_to_full;  ///< Full index of each free dof, increasing.
};

/// Indices (increasing) of the vertices inside the closed box, e.g. to clamp one end of a beam.
KHZ_REDUCED_API std::vector<int> vertices_in_box(const VertexMatrix& vertices,
                                                 const Eigen::AlignedBox3d& box);

}  // namespace khz::reduced
