// ReducedModel::precompute(): the reduced energy polynomials and masses from the FEM model
// (thesis §2.6), apart from the rest of ReducedModel so that reading a model file needs no FEM.
#include "detail/shared_stage.hpp"
#include "subspace/energy_precompute.hpp"

#include <khz/reduced/errors.hpp>
#include <khz/reduced/subspace/reduced_model.hpp>

#include <Eigen/Cholesky>

#include <array>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

namespace khz::reduced {

namespace {

// C = λ·11ᵀ (on the normal strains) + μ·diag(2, 2, 2, 1, 1, 1): factors of the unit parts.
detail::VoigtFactor lambda_factor() {
  detail::VoigtFactor factor = detail::VoigtFactor::Zero(6, 1);
  factor.topRows<3>().setOnes();
  return factor;
}

detail::VoigtFactor mu_factor() {
  detail::VoigtFactor factor = detail::VoigtFactor::Zero(6, 6);
  factor.diagonal() << std::sqrt(2.0), std::sqrt(2.0), std::sqrt(2.0), 1.0, 1.0, 1.0;
  return factor;
}

void check_basis(const FemModel& fem, const Eigen::MatrixXd& u) {
  if (u.rows() != fem.num_dofs()) {
    throw Error("ReducedModel: the basis has " + std::to_string(u.rows()) +
                " rows but the FEM model has " + std::to_string(fem.num_dofs()) + " dofs");
  }
  if (u.cols() == 0) throw Error("ReducedModel: the basis has no vectors");
  if (!u.allFinite()) throw Error("ReducedModel: the basis has a non-finite entry");
}

}  // namespace

ReducedModel ReducedModel::precompute(const FemModel& fem, Basis basis,
                                      const ReducedModelOptions& options) {
  const Eigen::MatrixXd& u = basis.vectors;
  // With a group, a bad basis on one process stops every process, before any partial sum.
  const ProgressCallback quiet;
  detail::SharedStage inputs(options.group, quiet, "reduced polynomials", 1);
  inputs.agree([&] { check_basis(fem, u); });
  const std::array<double, 4> sizes{
      static_cast<double>(fem.num_dofs()), static_cast<double>(fem.mesh().elements.rows()),
      static_cast<double>(fem.materials().size()), static_cast<double>(u.cols())};
  if (!detail::same_on_every_process(options.group, sizes)) {
    throw Error(
        "ReducedModel: the processes of the group were given different models or bases (every "
        "process must pass the same dofs, elements, materials and basis size)");
  }

  std::vector<std::vector<detail::VoigtFactor>> factors;
  for (const Material& material : fem.materials()) {
    if (material.is_stvk()) {
      factors.push_back({lambda_factor(), mu_factor()});
    } else {
      factors.push_back({detail::VoigtFactor(material.elasticity().llt().matrixL())});
    }
  }
  std::vector<std::vector<EnergyPolynomial>> energies =
      detail::precompute_group_energies(fem, u, factors, options.progress, options.group);

  std::vector<ReducedMaterialGroup> groups;
  for (std::size_t g = 0; g < energies.size(); ++g) {
    const Material& material = fem.materials()[g];
    const SparseMatrix mass = fem.unit_density_mass_matrix(static_cast<int>(g), options.mass);
    Eigen::MatrixXd reduced_mass = u.transpose() * (mass * u);
    reduced_mass = 0.5 * (reduced_mass + reduced_mass.transpose()).eval();
    groups.push_back({material, material.is_stvk() ? VoigtMatrix::Zero() : material.elasticity(),
                      1.0, std::move(energies[g]), std::move(reduced_mass)});
  }
  return ReducedModel(std::move(basis), std::move(groups), ReducedIntegratorDefaults{});
}

}  // namespace khz::reduced
