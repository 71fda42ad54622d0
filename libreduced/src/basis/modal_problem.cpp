#include "modal_problem.hpp"

#include "../mesh/union_find.hpp"
#include "generator_support.hpp"

#include <khz/reduced/errors.hpp>

#include <algorithm>
#include <string>

namespace khz::reduced::detail {

namespace {

void require_every_vertex_in_an_element(const VolumeMesh& mesh) {
  std::vector<bool> used(static_cast<std::size_t>(mesh.vertices.rows()), false);
  for (Eigen::Index e = 0; e < mesh.elements.rows(); ++e) {
    for (Eigen::Index a = 0; a < mesh.elements.cols(); ++a) {
      used[static_cast<std::size_t>(mesh.elements(e, a))] = true;
    }
  }
  const auto unused = std::find(used.begin(), used.end(), false);
  if (unused != used.end()) {
    const auto vertex = static_cast<std::int64_t>(unused - used.begin());
    throw MeshError("vertex " + std::to_string(vertex) +
                        " belongs to no element: it has no mass and no stiffness (remove unused "
                        "vertices before modal analysis)",
                    vertex);
  }
}

// Labels each vertex with its component's representative.
std::vector<Eigen::Index> component_labels(const VolumeMesh& mesh) {
  UnionFind sets(mesh.vertices.rows());
  for (Eigen::Index e = 0; e < mesh.elements.rows(); ++e) {
    for (Eigen::Index a = 1; a < mesh.elements.cols(); ++a) {
      sets.unite(mesh.elements(e, 0), mesh.elements(e, a));
    }
  }
  std::vector<Eigen::Index> labels(static_cast<std::size_t>(mesh.vertices.rows()));
  for (Eigen::Index v = 0; v < mesh.vertices.rows(); ++v) {
    labels[static_cast<std::size_t>(v)] = sets.find(v);
  }
  return labels;
}

}  // namespace

ModalProblem::ModalProblem(const FemModel& model, std::span<const int> fixed_vertices,
                           MassLumping lumping)
    : m_fixed(
          sorted_fixed_vertices(fixed_vertices, model.mesh().vertices.rows(), "modal analysis")),
      m_dofs(model.mesh().vertices.rows(), m_fixed) {
  require_every_vertex_in_an_element(model.mesh());
  SparseMatrix stiffness = model.stiffness_pattern();
  model.tangent_stiffness(Eigen::VectorXd::Zero(model.num_dofs()), stiffness);
  m_stiffness = m_dofs.restrict_matrix(stiffness);
  m_mass = m_dofs.restrict_matrix(model.mass_matrix(lumping));
  if (unconstrained()) {
    // K is singular along the rigid motions. σ < 0 makes K − σM positive definite; |σ| is tiny
    // next to the stiffness scale (the mean of diag K / diag M, near the top of the spectrum),
    // so shift-invert still resolves the low modes, and K − σM keeps a condition number
    // (≈ 1e7) that a Cholesky factorization handles to full working accuracy.
    const double scale = m_stiffness.diagonal().sum() / m_mass.diagonal().sum();
    m_shift = -1e-7 * scale;
  }
}

SparseCholesky ModalProblem::factorize_shifted() const {
  SparseCholesky cholesky;
  const SparseMatrix shifted = m_stiffness - m_shift * m_mass;
  if (!cholesky.try_factorize(shifted)) {
    try {
      cholesky.factorize(shifted);  // repeats the failure to get its message
    } catch (const SolverError& error) {
      if (unconstrained()) throw;
      throw SolverError(std::string("the stiffness matrix is singular on the free dofs: ") +
                        std::to_string(m_fixed.size()) +
                        (m_fixed.size() == 1 ? " fixed vertex leaves" : " fixed vertices leave") +
                        " a rigid motion free (fix at least 3 "
                        "non-collinear vertices of every connected part, or none) [" +
                        error.what() + "]");
    }
  }
  return cholesky;
}

namespace {

/// CHOLMOD's factorization as a SymmetricFactorization.
class CholeskyFactorization final : public SymmetricFactorization {
 public:
  explicit CholeskyFactorization(SparseCholesky cholesky) : m_cholesky(std::move(cholesky)) {}
  Eigen::MatrixXd solve(const Eigen::MatrixXd& rhs) override { return m_cholesky.solve(rhs); }

 private:
  SparseCholesky m_cholesky;
};

}  // namespace

std::unique_ptr<SymmetricFactorization> ModalProblem::factorize_shifted(
    const Factorize& factorize) const {
  if (factorize) return factorize(m_stiffness - m_shift * m_mass);
  return std::make_unique<CholeskyFactorization>(factorize_shifted());
}

Eigen::Index count_components(const VolumeMesh& mesh) {
  std::vector<Eigen::Index> labels = component_labels(mesh);
  std::sort(labels.begin(), labels.end());
  return static_cast<Eigen::Index>(std::unique(labels.begin(), labels.end()) - labels.begin());
}

Eigen::MatrixXd rigid_motions(const VolumeMesh& mesh) {
  const std::vector<Eigen::Index> labels = component_labels(mesh);
  std::vector<Eigen::Index> roots = labels;
  std::sort(roots.begin(), roots.end());
  roots.erase(std::unique(roots.begin(), roots.end()), roots.end());
  const Eigen::Index n = mesh.vertices.rows();
  Eigen::MatrixXd motions =
      Eigen::MatrixXd::Zero(3 * n, 6 * static_cast<Eigen::Index>(roots.size()));
  for (std::size_t c = 0; c < roots.size(); ++c) {
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    Eigen::Index count = 0;
    for (Eigen::Index v = 0; v < n; ++v) {
      if (labels[static_cast<std::size_t>(v)] != roots[c]) continue;
      centroid += mesh.vertices.row(v).transpose();
      ++count;
    }
    centroid /= static_cast<double>(count);
    const Eigen::Index first = 6 * static_cast<Eigen::Index>(c);
    for (Eigen::Index v = 0; v < n; ++v) {
      if (labels[static_cast<std::size_t>(v)] != roots[c]) continue;
      const Eigen::Vector3d x = mesh.vertices.row(v).transpose() - centroid;
      for (int axis = 0; axis < 3; ++axis) {
        motions(3 * v + axis, first + axis) = 1.0;
        motions.block<3, 1>(3 * v, first + 3 + axis) = Eigen::Vector3d::Unit(axis).cross(x);
      }
    }
  }
  return motions;
}

}  // namespace khz::reduced::detail
