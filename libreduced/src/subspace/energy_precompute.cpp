#include "subspace/energy_precompute.hpp"

#include "detail/shared_stage.hpp"

#include <khz/reduced/worker_threads.hpp>

#include <Eigen/Dense>

#include <algorithm>
#include <array>
#include <cmath>
#include <span>
#include <utility>

#include <omp.h>

namespace khz::reduced::detail {

namespace {

// Quadrature points per rank-k update: enough rows (6 per point and part) for the update to run
// at matrix-multiply speed, few enough that every thread's buffer stays small.
constexpr int points_per_block = 128;

Eigen::Index pair_count(Eigen::Index r) { return r * (r + 1) / 2; }
// Colexicographic position of q_j q_k (j ≤ k) among the quadratic monomials.
Eigen::Index pair_index(Eigen::Index j, Eigen::Index k) { return k * (k + 1) / 2 + j; }

using Voigt = Eigen::Matrix<double, 6, 1>;

// The Voigt vector (engineering shears, Material's convention) of sym(M) for a 3×3 matrix M,
// scaled so that the symmetric part's diagonal has weight `diagonal` and the shears weight 1.
Voigt symmetric_voigt(const Eigen::Matrix3d& m, double diagonal) {
  Voigt v;
  v << diagonal * m(0, 0), diagonal * m(1, 1), diagonal * m(2, 2), m(1, 2) + m(2, 1),
      m(0, 2) + m(2, 0), m(0, 1) + m(1, 0);
  return v;
}

// Everything one thread needs for its share of the quadrature points.
struct ThreadWork {
  ThreadWork(Eigen::Index nodes, Eigen::Index r, Eigen::Index monomials,
             const std::vector<VoigtFactor>& factors)
      : element_basis(3 * nodes, r), gradients(r), strains(6, monomials) {
    for (const VoigtFactor& factor : factors) {
      rows.emplace_back(monomials, points_per_block * factor.cols());
      sums.push_back(Eigen::MatrixXd::Zero(monomials, monomials));
    }
  }

  Eigen::MatrixXd element_basis;                     // U restricted to one element's dofs
  std::vector<Eigen::Matrix3d> gradients;            // G^i = ∂(U_i)/∂X at a quadrature point
  Eigen::Matrix<double, 6, Eigen::Dynamic> strains;  // Voigt ε^i, then η^{jk}, per monomial
  std::vector<Eigen::MatrixXd> rows;  // per part: pending rows √w Lᵀ(ε | η), as columns
  std::vector<Eigen::MatrixXd> sums;  // per part: Σ rows rowsᵀ (lower triangle)
  Eigen::Index pending = 0;           // quadrature points in `rows`
};

// Strain monomials at one quadrature point (thesis eq. 2.1, §2.6.1). With G(q) = Σ_i q_i G^i,
// the Green strain is E = ε + η, ε = Σ_i q_i sym(G^i) and η = ½GᵀG = Σ_{j≤k} q_j q_k η^{jk}.
void strain_monomials(
    const Eigen::Ref<const Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>>&
        shape_gradients,
    ThreadWork& work) {
  const Eigen::Index r = work.gradients.size();
  for (Eigen::Index i = 0; i < r; ++i) {
    Eigen::Matrix3d g = Eigen::Matrix3d::Zero();
    for (Eigen::Index a = 0; a < shape_gradients.rows(); ++a) {
      g.noalias() += work.element_basis.block<3, 1>(3 * a, i) * shape_gradients.row(a);
    }
    work.gradients[i] = g;
    work.strains.col(i) = symmetric_voigt(g, 1.0);
  }
  for (Eigen::Index k = 0; k < r; ++k) {
    for (Eigen::Index j = 0; j <= k; ++j) {
      const Eigen::Matrix3d product = work.gradients[j].transpose() * work.gradients[k];
      // q_j q_k with j < k collects ½(G^jᵀG^k + G^kᵀG^j); the square term ½ G^jᵀG^j.
      work.strains.col(r + pair_index(j, k)) =
          j < k ? symmetric_voigt(product, 1.0) : symmetric_voigt(0.5 * product, 1.0);
    }
  }
}

void flush(ThreadWork& work) {
  if (work.pending == 0) return;  // Eigen's blocking heuristic divides by the update's depth
  for (std::size_t part = 0; part < work.rows.size(); ++part) {
    const Eigen::Index columns = work.pending * work.rows[part].cols() / points_per_block;
    work.sums[part].selfadjointView<Eigen::Lower>().rankUpdate(work.rows[part].leftCols(columns));
  }
  work.pending = 0;
}

// Sorts up to four indices in place (a tiny insertion sort).
template <std::size_t N>
std::array<int, N> sorted(std::array<int, N> indices) {
  for (std::size_t i = 1; i < N; ++i) {
    for (std::size_t j = i; j > 0 && indices[j - 1] > indices[j]; --j) {
      std::swap(indices[j - 1], indices[j]);
    }
  }
  return indices;
}

// Reads E(q) = ½ zᵀ S z off the Gram matrix S (lower triangle) of z = (q, q_j q_k).
EnergyPolynomial polynomial_from_gram(const Eigen::MatrixXd& gram, Eigen::Index r) {
  EnergyPolynomial polynomial = EnergyPolynomial::zero(r);
  polynomial.quadratic = gram.topLeftCorner(r, r).selfadjointView<Eigen::Lower>();
  std::vector<std::array<int, 2>> pairs;
  for (int k = 0; k < r; ++k) {
    for (int j = 0; j <= k; ++j) pairs.push_back({j, k});
  }
  const Eigen::Index count = pair_count(r);
  for (Eigen::Index p = 0; p < count; ++p) {
    const auto [j, k] = pairs[p];
    // Cubic: the two cross terms ½(ε·η + η·ε) of ½‖Lᵀ(ε+η)‖² give q_i q_j q_k S(jk, i).
    for (int i = 0; i < r; ++i) {
      const auto t = sorted<3>({i, j, k});
      polynomial.cubic[EnergyPolynomial::cubic_index(t[0], t[1], t[2])] += gram(r + p, i);
    }
    // Quartic: ½ Σ_{p,s} S(p,s) m_p m_s; the lower triangle counts off-diagonal pairs once.
    for (Eigen::Index s = 0; s <= p; ++s) {
      const auto [l, m] = pairs[s];
      const auto t = sorted<4>({j, k, l, m});
      polynomial.quartic[EnergyPolynomial::quartic_index(t[0], t[1], t[2], t[3])] +=
          (s == p ? 0.5 : 1.0) * gram(r + p, r + s);
    }
  }
  return polynomial;
}

}  // namespace

std::vector<std::vector<EnergyPolynomial>> precompute_group_energies(
    const FemModel& fem, const Eigen::MatrixXd& basis,
    const std::vector<std::vector<VoigtFactor>>& part_factors, const ProgressCallback& progress,
    WorkGroup* group) {
  const VolumeMesh& mesh = fem.mesh();
  const Eigen::Index r = basis.cols();
  const Eigen::Index monomials = r + pair_count(r);
  const Eigen::Index nodes = mesh.elements.cols();
  const int points = fem.quadrature_points_per_element();
  const auto groups = static_cast<int>(part_factors.size());

  std::vector<std::vector<Eigen::Index>> group_elements(groups);
  for (Eigen::Index e = 0; e < mesh.elements.rows(); ++e) {
    group_elements[mesh.element_groups.size() > 0 ? mesh.element_groups[e] : 0].push_back(e);
  }
  const Eigen::Index elements_per_block = std::max(1, points_per_block / points);
  const auto blocks_of = [&](int g) {
    return (static_cast<Eigen::Index>(group_elements[g].size()) + elements_per_block - 1) /
           elements_per_block;
  };
  std::int64_t total_blocks = 0;
  for (int g = 0; g < groups; ++g) total_blocks += blocks_of(g);
  SharedStage stage(group, progress, "reduced polynomials", total_blocks);

  const int threads = worker_threads();
  // A round of a few blocks per thread between checkpoints: progress and cancellation within
  // a fraction of a second, a negligible share of time spent meeting the other processes.
  const std::int64_t blocks_per_round = 4 * threads;
  std::vector<std::vector<EnergyPolynomial>> energies(groups);
  for (int g = 0; g < groups; ++g) {
    const std::vector<Eigen::Index>& elements = group_elements[g];
    std::vector<ThreadWork> work;
    for (int t = 0; t < threads; ++t) work.emplace_back(nodes, r, monomials, part_factors[g]);
    // This process's blocks of group g, each thread adding into its own sums.
    const auto accumulate = [&](std::int64_t first, std::int64_t last) {
#pragma omp parallel for schedule(static) num_threads(threads)
      for (std::int64_t block = first; block < last; ++block) {
        ThreadWork& mine = work[omp_get_thread_num()];
        const Eigen::Index end = std::min<Eigen::Index>(static_cast<Eigen::Index>(elements.size()),
                                                        (block + 1) * elements_per_block);
        for (Eigen::Index at = block * elements_per_block; at < end; ++at) {
          const Eigen::Index e = elements[at];
          for (Eigen::Index a = 0; a < nodes; ++a) {
            mine.element_basis.middleRows<3>(3 * a) = basis.middleRows<3>(3 * mesh.elements(e, a));
          }
          for (int q = 0; q < points; ++q) {
            strain_monomials(fem.shape_gradients(e, q), mine);
            const double root_weight = std::sqrt(fem.quadrature_weight(e, q));
            for (std::size_t part = 0; part < part_factors[g].size(); ++part) {
              const VoigtFactor& factor = part_factors[g][part];
              mine.rows[part].middleCols(mine.pending * factor.cols(), factor.cols()).noalias() =
                  root_weight * mine.strains.transpose() * factor;
            }
            if (++mine.pending == points_per_block) flush(mine);
          }
        }
      }
    };
    stage.run(blocks_of(g), blocks_per_round, accumulate);
    for (ThreadWork& mine : work) flush(mine);

    for (std::size_t part = 0; part < part_factors[g].size(); ++part) {
      Eigen::MatrixXd gram = std::move(work[0].sums[part]);
      for (std::size_t t = 1; t < work.size(); ++t) gram += work[t].sums[part];
      // Every process's partial Gram matrix, summed: the whole mesh's.
      if (stage.shared()) group->sum(std::span<double>(gram.data(), gram.size()));
      energies[g].push_back(polynomial_from_gram(gram, r));
    }
  }
  stage.finish();
  return energies;
}

}  // namespace khz::reduced::detail
