#include <khz/reduced/basis/simulation_data_basis.hpp>
#include <khz/reduced/errors.hpp>

#include "basis/generator_support.hpp"
#include "detail/number_text.hpp"

#include <cmath>
#include <string>
#include <utility>

namespace khz::reduced {
namespace {

constexpr std::string_view who = "simulation_data_basis";

std::string vertex_of_dof(Eigen::Index dof) {
  return "vertex " + std::to_string(dof / 3) + " (dof " + std::to_string(dof) + ")";
}

void check_snapshots(const FemModel& model, const Eigen::MatrixXd& snapshots,
                     const std::vector<int>& fixed, double fixed_tolerance) {
  if (snapshots.rows() != model.num_dofs()) {
    throw Error("simulation_data_basis: the snapshots have " + std::to_string(snapshots.rows()) +
                " rows, but the model has " + std::to_string(model.num_dofs()) + " dofs");
  }
  if (snapshots.cols() == 0) throw Error("simulation_data_basis: no snapshots given");
  for (Eigen::Index s = 0; s < snapshots.cols(); ++s) {
    for (Eigen::Index dof = 0; dof < snapshots.rows(); ++dof) {
      if (!std::isfinite(snapshots(dof, s))) {
        throw Error("simulation_data_basis: snapshot " + std::to_string(s) + " is not finite at " +
                    vertex_of_dof(dof));
      }
    }
  }
  const double largest = snapshots.cwiseAbs().maxCoeff();
  const double allowed = fixed_tolerance * largest;
  for (Eigen::Index s = 0; s < snapshots.cols(); ++s) {
    for (int v : fixed) {
      const Eigen::Vector3d moved = snapshots.col(s).segment<3>(3 * Eigen::Index{v});
      if (moved.cwiseAbs().maxCoeff() > allowed) {
        throw Error("simulation_data_basis: snapshot " + std::to_string(s) +
                    " moves fixed vertex " + std::to_string(v) + " by " +
                    detail::number_text(moved.norm()) +
                    " m (allowed: " + detail::number_text(allowed) +
                    " m per component, fixed_tolerance × the largest displacement)");
      }
    }
  }
}

}  // namespace

// Thesis §2.8 (after [KLM01]) and §2.13.1 ("re-simulation"): mass-PCA of the deformation
// trajectory of an unreduced simulation.
Basis simulation_data_basis(const FemModel& model, std::span<const int> fixed_vertices,
                            const Eigen::MatrixXd& snapshots, int basis_size,
                            const SimulationDataBasisOptions& options) {
  if (!std::isfinite(options.fixed_tolerance) || options.fixed_tolerance < 0.0) {
    throw Error("simulation_data_basis: fixed_tolerance must be finite and non-negative, got " +
                detail::number_text(options.fixed_tolerance));
  }
  const std::vector<int> fixed =
      detail::sorted_fixed_vertices(fixed_vertices, model.mesh().num_vertices(), who);
  check_snapshots(model, snapshots, fixed, options.fixed_tolerance);
  if (basis_size < 1 || basis_size > snapshots.cols()) {
    throw Error("simulation_data_basis: basis_size " + std::to_string(basis_size) +
                " is outside [1, " + std::to_string(snapshots.cols()) +
                "] (the number of snapshots)");
  }

  PcaOptions pca_options;
  pca_options.basis_size = basis_size;
  pca_options.metric = options.metric;
  pca_options.rank_tolerance = options.rank_tolerance;
  pca_options.progress = options.progress;
  PcaResult pca = principal_components(snapshots, model.mass_matrix(), pca_options);

  Basis basis;
  basis.vectors = std::move(pca.basis);
  detail::zero_fixed_rows(basis.vectors, fixed);
  basis.fixed_vertices = fixed;
  basis.recipe = "simulation data: " + std::to_string(snapshots.cols()) + " snapshots, " +
                 detail::pca_name(options.metric) + " to r=" + std::to_string(basis_size);
  return basis;
}

}  // namespace khz::reduced
