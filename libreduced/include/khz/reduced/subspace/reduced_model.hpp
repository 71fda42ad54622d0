#pragma once
// A reduced deformable model: basis, exact energy polynomials per material group, reduced mass.

#include <khz/reduced/basis/basis.hpp>
#include <khz/reduced/export.hpp>
#include <khz/reduced/fem/fem_model.hpp>
#include <khz/reduced/fem/material.hpp>
#include <khz/reduced/progress.hpp>
#include <khz/reduced/solvers/newmark_parameters.hpp>
#include <khz/reduced/subspace/energy_polynomial.hpp>
#include <khz/reduced/subspace/reduced_newmark.hpp>
#include <khz/reduced/work_group.hpp>

#include <Eigen/Core>

#include <vector>

namespace khz::reduced {

/// One material group's share of a reduced model (thesis §2.11). Lamé parameters, an elasticity
/// scale and the density enter the energy and the mass linearly, so each group keeps its parts
/// apart and the model re-weights them when the material changes, without a new precompute:
/// - StVK groups: parts = {E at λ = 1, μ = 0; E at λ = 0, μ = 1}; weights (λ, μ).
/// - General linear groups: parts = {E at the elasticity C₀ given at precompute}; weight s, so
///   the runtime elasticity is s·C₀ (an arbitrary new C would need a new precompute).
struct KHZ_REDUCED_API ReducedMaterialGroup {
  /// The group's current material (λ, μ or s·C₀, and ρ). For general groups, elasticity() is
  /// s·C₀ and `reference_elasticity` holds C₀.
  Material material;
  VoigtMatrix reference_elasticity = VoigtMatrix::Zero();  ///< C₀ (general groups; Pa).
  double elasticity_scale = 1.0;                           ///< s (general groups).
  std::vector<EnergyPolynomial> parts;                     ///< See above; 2 (StVK) or 1.
  /// UᵀM_gU at unit density (m³·(m per unit q)²): the reduced mass is Σ_g ρ_g times this.
  Eigen::MatrixXd unit_density_mass;

  /// The weights that multiply `parts`: (λ, μ) for StVK, (s) for general groups.
  std::vector<double> part_weights() const;
};

/// Integrator settings a model file carries, so a prepared model runs as it was tuned.
struct KHZ_REDUCED_API ReducedIntegratorDefaults {
  NewmarkParameters newmark;       ///< Δt, β̃, γ̃, Rayleigh α and β.
  int max_newton_iterations = 1;   ///< j_max (thesis §2.9: one, semi-implicit).
  double newton_tolerance = 1e-9;  ///< Relative residual at which Newton stops early.

  /// These settings as make_reduced_newmark() options (no acceleration limit): what a model's user
  /// passes to its integrator.
  ReducedNewmarkOptions newmark_options() const;
};

/// Options of ReducedModel::precompute().
struct ReducedModelOptions {
  /// Mass matrix used for the reduced mass (consistent, as the bases are mass-orthonormal in it).
  MassLumping mass = MassLumping::consistent;
  /// Reports stage "reduced polynomials" (units: element blocks, counted over the whole group
  /// when there is one); false cancels (Cancelled).
  ProgressCallback progress;
  /// Processes that share the precompute (e.g. khz::mpi::MpiWorkGroup), or null for this one
  /// alone. With a group, every process calls precompute() with the same model and basis; each
  /// sums the polynomials over its share of the elements, the shares are added, and every
  /// process returns the whole model, equal to a single process's to round-off. A failure or a
  /// cancel on any process ends the call on every process (Error naming the rank, Cancelled).
  WorkGroup* group = nullptr;
};

/// A reduced nonlinear deformable model (thesis §2.5–§2.6, §2.11): the basis U (3n×r), the exact
/// reduced strain energy of every material group as a quartic polynomial in q, and the reduced
/// mass. Time stepping uses energy_polynomial() through PolynomialForces and mass() as M̃.
class KHZ_REDUCED_API ReducedModel {
 public:
  /// Precomputes the energy polynomials of `fem` in `basis` (thesis §2.6.3), by one symmetric
  /// rank-k update per material part over all quadrature points (DESIGN.md §3), in parallel.
  /// @throws Error if the basis does not have fem.num_dofs() rows, has no columns or a
  ///         non-finite entry; Cancelled.
  static ReducedModel precompute(const FemModel& fem, Basis basis,
                                 const ReducedModelOptions& options = {});
  /// Assembles a model from stored parts (model files): every size, material and polynomial is
  /// validated. @throws Error naming the first inconsistency.
  static ReducedModel from_parts(Basis basis, std::vector<ReducedMaterialGroup> groups,
                                 const ReducedIntegratorDefaults& defaults);

  Eigen::Index dimension() const noexcept { return m_basis.size(); }  ///< r.
  const Basis& basis() const noexcept { return m_basis; }
  const std::vector<ReducedMaterialGroup>& groups() const noexcept { return m_groups; }
  const ReducedIntegratorDefaults& defaults() const noexcept { return m_defaults; }
  /// @throws Error (ReducedNewmarkOptions::validate()'s) if the defaults are invalid.
  void set_defaults(const ReducedIntegratorDefaults& defaults);

  /// Sets an StVK group's Lamé parameters (Pa). @throws Error for a general group or invalid
  /// values (as Material::stvk_lame).
  void set_lame(int group, LameParameters lame);
  /// Sets a general group's elasticity to s·C₀. @throws Error for an StVK group or s ≤ 0.
  void set_elasticity_scale(int group, double scale);
  /// Sets a group's density (kg/m³). @throws Error unless ρ > 0 and finite.
  void set_density(int group, double density);

  /// The model's energy polynomial for the current materials: Σ_g Σ_p w_gp E_gp.
  EnergyPolynomial energy_polynomial() const;
  /// The same into `out`, reusing its storage when it already has this model's size.
  void energy_polynomial(EnergyPolynomial& out) const;
  /// M̃ = Σ_g ρ_g UᵀM_gU (r×r, symmetric positive definite; the identity for a
  /// mass-orthonormal basis at the densities it was made with).
  Eigen::MatrixXd mass() const;

  /// The model in the first r' basis vectors (thesis §2.11): polynomials truncated, basis and
  /// masses cut. @throws Error unless 1 ≤ r' ≤ r.
  ReducedModel truncated(Eigen::Index dimension) const;

 private:
  ReducedModel(Basis basis, std::vector<ReducedMaterialGroup> groups,
               const ReducedIntegratorDefaults& defaults);
  ReducedMaterialGroup& group_at(int group, const char* caller);

  Basis m_basis;
  std::vector<ReducedMaterialGroup> m_groups;
  ReducedIntegratorDefaults m_defaults;
};

}  // namespace khz::reduced
