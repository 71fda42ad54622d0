#pragma once
// How a reduced object's basis U is made: linear modes (with or without modal derivatives), a
// sketch basis from recorded loads, or mass-PCA of a full simulation.

#include <khz/reduced/basis/mass_pca.hpp>
#include <khz/reduced/fem/fem_model.hpp>
#include <khz/reduced/solvers/full_newmark.hpp>
#include <khz/reduced/solvers/static_solver.hpp>

#include <cstdint>
#include <filesystem>
#include <string>

namespace khz::scene {

/// The basis generator (JSON model.basis.method).
enum class BasisMethod {
  /// "modes": the k lowest linear modes (compute_linear_modes), with modal derivatives,
  /// eq. 2.52 weighting and mass-PCA to r vectors (modal_derivative_basis) when
  /// modal_derivatives is on, or the first r ≤ k modes when it is off.
  modes,
  /// "sketch": recorded force loads → static solves → mass-PCA (sketch_basis, §2.8.2).
  sketch,
  /// "simulation_data": mass-PCA of the displacements of a full simulation driven by recorded
  /// force loads (simulation_data_basis, §2.8).
  simulation_data,
};

/// The full simulation whose snapshots a simulation-data basis is made of (JSON
/// basis.simulation). One run of reduced::FullNewmark from rest: every load of the load file in
/// turn is held for hold_steps steps and then removed for release_steps steps; the displacement
/// after every snapshot_every-th step is a snapshot.
struct SimulationRunDescription {
  int hold_steps = 0;      ///< "hold_steps", ≥ 1, required: steps each load is applied.
  int release_steps = 0;   ///< "release_steps", ≥ 0: force-free steps after each load.
  int snapshot_every = 1;  ///< "snapshot_every", ≥ 1: steps between snapshots.
  /// The run's integrator, with the library's defaults: JSON "time_step" (Δt, s, > 0),
  /// "mass_damping" (Rayleigh α, 1/s, ≥ 0) and "stiffness_damping" (Rayleigh β, s, ≥ 0) set
  /// its NewmarkParameters, "max_newton_iterations" (≥ 1) its own; beta, gamma, mass and
  /// tolerance are not keys.
  reduced::FullNewmarkOptions integrator;
};

/// A reduced object's basis recipe (JSON model.basis). Members list their JSON key and the
/// library option they map to; settings of another method than `method` keep their defaults
/// (the reader refuses them in the file).
struct BasisDescription {
  BasisMethod method = BasisMethod::modes;  ///< "method": "modes" | "sketch" | "simulation_data".

  /// "r": basis vectors (≥ 1). modes with derivatives: ModalDerivativeBasisOptions::basis_size,
  /// default 30, at most k + k(k+1)/2 with anchors and k + k² without; modes without
  /// derivatives: default k, at most k; sketch (SketchBasisOptions::basis_size) and
  /// simulation_data (simulation_data_basis's basis_size): required.
  int basis_size = 30;

  // --- modes ---
  /// "k": deformation modes (≥ 1); LinearModesOptions::num_modes.
  int num_modes = 20;
  /// "modal_derivatives": add the modal derivatives and reduce by mass-PCA
  /// (modal_derivative_basis) rather than keep the first r modes.
  bool modal_derivatives = true;
  /// "mass": "consistent" | "lumped"; LinearModesOptions::mass.
  reduced::MassLumping mass = reduced::MassLumping::consistent;
  /// "tolerance": ARPACK's relative residual, ≥ 0, 0 for machine precision;
  /// LinearModesOptions::tolerance.
  double tolerance = 0.0;
  /// "max_restarts": ≥ 1; LinearModesOptions::max_restarts.
  int max_restarts = 300;

  // --- every mass-PCA (modes with derivatives, sketch, simulation_data) ---
  /// "metric": "mass" | "lumped_mass" | "euclidean"; ModalDerivativeBasisOptions::metric,
  /// SketchBasisOptions::metric, SimulationDataBasisOptions::metric.
  reduced::PcaMetric metric = reduced::PcaMetric::mass;
  /// "rank_tolerance": in [0, 1) (sketch, simulation_data); the options' rank_tolerance.
  double rank_tolerance = 1e-10;

  // --- sketch and simulation_data ---
  /// "loads": the recorded force loads (CSV, reduced::parse_force_loads(); vertex indices of the
  /// volume mesh), as written in the scene; required for these methods.
  std::string loads;
  /// `loads` resolved against the scene file's directory (absolute).
  std::filesystem::path loads_path;

  // --- sketch (SketchBasisOptions, same names) ---
  double force_separation = 0.0;          ///< "force_separation": δ_f (N), ≥ 0.
  double force_kernel_width = 0.0;        ///< "force_kernel_width": h_f (N), ≥ 0.
  double deformation_separation = 0.0;    ///< "deformation_separation": δ_u (m·√kg), ≥ 0.
  double deformation_kernel_width = 0.0;  ///< "deformation_kernel_width": h_u (m·√kg), ≥ 0.
  /// "static_solve": load_steps, max_iterations, tolerance, line_search (progress is not a key).
  reduced::StaticSolveOptions static_solve;
  bool skip_failed_solves = false;  ///< "skip_failed_solves".

  // --- simulation_data ---
  SimulationRunDescription simulation;  ///< "simulation" (required for this method).
  /// "fixed_tolerance": ≥ 0; SimulationDataBasisOptions::fixed_tolerance.
  double fixed_tolerance = 1e-12;
};

}  // namespace khz::scene
