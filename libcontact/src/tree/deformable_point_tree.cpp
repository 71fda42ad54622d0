#include <khz/contact/tree/deformable_point_tree.hpp>
#include <khz/reduced/subspace/embedded_surface.hpp>

#include <khz/reduced/stage_progress.hpp>
#include <khz/reduced/worker_threads.hpp>
#include "tree/subtree_leaves.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>

namespace khz::contact {

namespace {

std::size_t index(Eigen::Index i) noexcept { return static_cast<std::size_t>(i); }

// Points embedded per progress report.
constexpr Eigen::Index embedding_chunk = 1 << 14;

/// U_s and ΔN_s of every tree point, in tree point order, from libreduced's embedding.
struct SampledModes {
  std::vector<double> displacement;
  std::vector<double> normal;
};

SampledModes sample_modes(const PointTree& tree, const reduced::MeshEmbedding& embedding,
                          const Eigen::MatrixXd& basis, const ProgressCallback& progress) {
  if (basis.cols() < 1) throw Error("DeformablePointTree: the basis has no columns");
  const Eigen::Index count = tree.num_points();
  const Eigen::Index block = 3 * basis.cols();
  SampledModes modes;
  modes.displacement.resize(index(block * count));
  modes.normal.resize(index(block * count));
  // In chunks, for progress and cancellation: locating points is the slow part (~2 µs each).
  reduced::StageProgress stage(progress, "embedding points", count);
  for (Eigen::Index begin = 0; begin < count; begin += embedding_chunk) {
    const Eigen::Index size = std::min(embedding_chunk, count - begin);
    const reduced::EmbeddedSurface surface(
        embedding, tree.pointshell().points.middleRows(begin, size),
        tree.pointshell().normals.middleRows(begin, size), basis);
    for (Eigen::Index s = 0; s < size; ++s) {
      // Each view is one contiguous row-major 3×r block, the layout kept here.
      std::memcpy(modes.displacement.data() + block * (begin + s),
                  surface.displacement_modes(s).data(), sizeof(double) * index(block));
      std::memcpy(modes.normal.data() + block * (begin + s), surface.normal_modes(s).data(),
                  sizeof(double) * index(block));
    }
    stage.advance(size);
  }
  stage.finish();
  return modes;
}

}  // namespace

DeformablePointTree::DeformablePointTree(PointTree tree, const reduced::MeshEmbedding& embedding,
                                         const Eigen::MatrixXd& basis,
                                         const ProgressCallback& progress)
    : m_tree(std::move(tree)), m_dimension(basis.cols()) {
  SampledModes modes = sample_modes(m_tree, embedding, basis, progress);
  m_displacement_modes = std::move(modes.displacement);
  m_normal_modes = std::move(modes.normal);
  compute_radius_coefficients(progress);
  compute_displacement_bound();
}

DeformablePointTree::DeformablePointTree(PointTree tree, Eigen::Index dimension,
                                         std::vector<double> displacement_modes,
                                         std::vector<double> normal_modes,
                                         const ProgressCallback& progress)
    : m_tree(std::move(tree)),
      m_dimension(dimension),
      m_displacement_modes(std::move(displacement_modes)),
      m_normal_modes(std::move(normal_modes)) {
  if (m_dimension < 1) {
    throw Error("DeformablePointTree: dimension " + std::to_string(m_dimension) + " is below 1");
  }
  const std::size_t expected = index(3 * m_dimension * m_tree.num_points());
  const auto check = [&](const std::vector<double>& modes, const char* name) {
    if (modes.size() != expected) {
      throw Error(std::string("DeformablePointTree: ") + name + " has " +
                  std::to_string(modes.size()) + " entries, expected " + std::to_string(expected) +
                  " (3r per point)");
    }
    for (std::size_t k = 0; k < modes.size(); ++k) {
      if (!std::isfinite(modes[k])) {
        throw Error(std::string("DeformablePointTree: ") + name + " of point " +
                    std::to_string(k / index(3 * m_dimension)) + " is not finite");
      }
    }
  };
  check(m_displacement_modes, "displacement_modes");
  check(m_normal_modes, "normal_modes");
  compute_radius_coefficients(progress);
  compute_displacement_bound();
}

// The BD-tree coefficients of eq. 3.12 for sphere bounds over points [James & Pai 2004, §4;
// thesis §3.7]. For node i with centre point c and any point s of its subtree, eq. 3.6 gives
// exactly, for every q,
//   p_s(q) − p_c(q) = (P_s − P_c) + Σ_j (U_s,j − U_c,j) q_j        (U_s,j: column j of U_s)
// and by the triangle inequality
//   ‖p_s(q) − p_c(q)‖ ≤ ‖P_s − P_c‖ + Σ_j ‖U_s,j − U_c,j‖ |q_j| ≤ R_i0 + Σ_j a_ij |q_j|
// with R_i0 = max_s ‖P_s − P_c‖ (PointTree) and a_ij = max_s ‖U_s,j − U_c,j‖ (here). No
// linearization is involved, so the bound holds for large q too. Each a_ij is attained by some
// s, and for q = t e_j that point has ‖p_s − p_c‖ ≥ |t| a_ij − R_i0: the bound exceeds the true
// subtree radius by at most 2 R_i0, whatever t — the coefficients are as small as a bound of
// this form allows.
void DeformablePointTree::compute_radius_coefficients(const ProgressCallback& progress) {
  const Eigen::Index r = m_dimension;
  const Eigen::Index internal = m_tree.num_internal_nodes();
  m_radius_coefficients.assign(index(r * internal), 0.0);
  const std::vector<detail::LeafRange> leaves = detail::subtree_leaves(m_tree);
  reduced::StageProgress stage(progress, "BD-tree coefficients", internal);
  for (int level = 0; level + 1 < m_tree.num_levels(); ++level) {
    const Eigen::Index begin = m_tree.level_begin(level);
    const Eigen::Index end = m_tree.level_end(level);
#pragma omp parallel for num_threads(reduced::worker_threads()) schedule(dynamic, 16)
    for (Eigen::Index n = begin; n < end; ++n) {
      double* a = m_radius_coefficients.data() + r * n;  // squared norms until the end
      const double* uc = m_displacement_modes.data() + 3 * r * m_tree.node(n).point;
      for (auto leaf = leaves[index(n)].begin; leaf < leaves[index(n)].end; ++leaf) {
        const double* us = m_displacement_modes.data() + 3 * r * m_tree.node(leaf).point;
        for (Eigen::Index j = 0; j < r; ++j) {
          const double dx = us[j] - uc[j];
          const double dy = us[r + j] - uc[r + j];
          const double dz = us[2 * r + j] - uc[2 * r + j];
          a[j] = std::max(a[j], dx * dx + dy * dy + dz * dz);
        }
      }
      for (Eigen::Index j = 0; j < r; ++j) a[j] = std::sqrt(a[j]);
    }
    stage.advance(end - begin);
  }
  stage.finish();
}

void DeformablePointTree::compute_displacement_bound() noexcept {
  m_displacement_bound = 0.0;
  for (Eigen::Index s = 0; s < m_tree.num_points(); ++s) {
    m_displacement_bound = std::max(m_displacement_bound, displacement_modes(s).norm());
  }
}

double DeformablePointTree::bounding_radius(
    Eigen::Index node, const Eigen::Ref<const Eigen::VectorXd>& abs_q) const noexcept {
  assert(node >= 0 && node < m_tree.num_nodes() && abs_q.size() == m_dimension);
  if (node >= m_tree.num_internal_nodes()) return 0.0;
  const double* a = m_radius_coefficients.data() + m_dimension * node;
  double radius = m_tree.node(node).rest_radius;
  for (Eigen::Index j = 0; j < m_dimension; ++j) radius += a[j] * abs_q[j];
  return radius;
}

}  // namespace khz::contact
