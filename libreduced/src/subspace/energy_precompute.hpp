#pragma once
// Precomputation of reduced energy polynomials by symmetric rank-k updates (thesis §2.6.3,
// DESIGN.md §3).

#include <khz/reduced/fem/fem_model.hpp>
#include <khz/reduced/progress.hpp>
#include <khz/reduced/subspace/energy_polynomial.hpp>
#include <khz/reduced/work_group.hpp>

#include <Eigen/Core>

#include <vector>

namespace khz::reduced::detail {

/// A material part: energy density ½ ‖Lᵀ E_v‖² with E_v the Green strain in Voigt form, i.e.
/// elasticity C = L Lᵀ (L is 6×k).
using VoigtFactor = Eigen::Matrix<double, 6, Eigen::Dynamic>;

/// For every material group g and each factor in part_factors[g], the reduced energy polynomial
/// of g's elements alone under that part's elasticity, in the basis U (3n×r).
/// With a `group`, each process sums its share of the elements and the shares are added (every
/// process gets the whole result); null: this process alone.
/// @throws Cancelled if `progress` says stop (on any process of the group); Error if a process
///         of the group failed.
std::vector<std::vector<EnergyPolynomial>> precompute_group_energies(
    const FemModel& fem, const Eigen::MatrixXd& basis,
    const std::vector<std::vector<VoigtFactor>>& part_factors, const ProgressCallback& progress,
    WorkGroup* group);

}  // namespace khz::reduced::detail
