#pragma once
// How a reduced object's basis U is made: linear modes (with or without modal derivatives), a
// sketch basis from recorded loads, or mass-PCA of a full simulation.

#include <khz/reduced/basis/modal_derivative_basis.hpp>
#include <khz/reduced/basis/simulation_data_basis.hpp>
#include <khz/reduced/basis/sketch_basis.hpp>
#include <khz/reduced/solvers/full_newmark.hpp>

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

/// A reduced object's basis recipe (JSON model.basis): the options of the library's generator
/// for `method`, with the library's defaults. The JSON keys are the library's names unless
/// said otherwise; the other methods' options keep their defaults (the reader refuses their
/// keys in the file).
struct BasisDescription {
  BasisMethod method = BasisMethod::modes;  ///< "method": "modes" | "sketch" | "simulation_data".

  // --- modes ---
  /// "modal_derivatives": add the modal derivatives and reduce by mass-PCA
  /// (modal_derivative_basis) rather than keep the first r modes.
  bool modal_derivatives = true;
  /// "k" → modes.num_modes (≥ 1), "mass", "tolerance" (≥ 0, 0 for machine precision) and
  /// "max_restarts" (≥ 1) → modes (LinearModesOptions); with modal derivatives also "metric"
  /// and "r" → basis_size (default 30, at most k + k(k+1)/2 with anchors and k + k² without).
  /// Without them only `modes` is used, and "r" → basis_size is the number of modes kept
  /// (default k, at most k). derivatives and progress are not keys.
  reduced::ModalDerivativeBasisOptions modal;

  // --- sketch and simulation_data ---
  /// "loads": the recorded force loads (CSV, reduced::parse_force_loads(); vertex indices of the
  /// volume mesh), as written in the scene; required for these methods.
  std::string loads;
  /// `loads` resolved against the scene file's directory (absolute).
  std::filesystem::path loads_path;

  // --- sketch ---
  /// "r" → basis_size (≥ 1, required), "metric", "rank_tolerance" (in [0, 1)),
  /// "force_separation", "force_kernel_width", "deformation_separation",
  /// "deformation_kernel_width" (each ≥ 0), "static_solve" {load_steps, max_iterations,
  /// tolerance, line_search} and "skip_failed_solves". progress is not a key.
  reduced::SketchBasisOptions sketch;

  // --- simulation_data ---
  /// "r" (≥ 1, required): simulation_data_basis()'s basis_size.
  int simulation_data_basis_size = 0;
  /// "metric", "rank_tolerance" (in [0, 1)) and "fixed_tolerance" (≥ 0). progress is not a key.
  reduced::SimulationDataBasisOptions simulation_data;
  SimulationRunDescription simulation;  ///< "simulation" (required for this method).

  /// "r": the basis size of `method`.
  int basis_size() const noexcept {
    switch (method) {
      case BasisMethod::modes:
        return modal.basis_size;
      case BasisMethod::sketch:
        return sketch.basis_size;
      case BasisMethod::simulation_data:
        break;
    }
    return simulation_data_basis_size;
  }
};

}  // namespace khz::scene
