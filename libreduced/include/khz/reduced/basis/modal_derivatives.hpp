#pragma once
// Modal derivatives: how the linear modes change as the object deforms along them (thesis
// §2.8.3, eq. 2.45–2.47; unconstrained objects §2.8.7, eq. 2.60).

#include <khz/reduced/basis/linear_modes.hpp>
#include <khz/reduced/export.hpp>
#include <khz/reduced/fem/fem_model.hpp>
#include <khz/reduced/progress.hpp>
#include <khz/reduced/solvers/symmetric_factorization.hpp>
#include <khz/reduced/work_group.hpp>

#include <Eigen/Core>

#include <array>
#include <vector>

namespace khz::reduced {

/// Options of compute_modal_derivatives().
struct ModalDerivativesOptions {
  /// Right-hand sides solved together (one pass over the factor per block, or one MINRES
  /// block): larger blocks are faster and need 3n × block_size doubles more memory.
  int block_size = 64;
  /// Unconstrained objects only: MINRES stops when ‖b − A x‖ ≤ tolerance·‖b‖ for each
  /// right-hand side of the deflated system (in the norm of the preconditioner).
  double tolerance = 1e-10;
  /// Unconstrained objects only: MINRES iterations per block before SolverError.
  int max_iterations = 2000;
  /// Reports stage "Hessian contractions" (one per mode) and "modal derivatives" (one per
  /// derivative). Cancel by returning false.
  ProgressCallback progress;
  /// The processes that share the computation (e.g. MPI ranks, khz/mpi/mpi_work_group.hpp),
  /// each calling compute_modal_derivatives() with the same model, modes and options; null:
  /// this process alone. Each process contracts its share of the modes and solves its share of
  /// the derivatives (whole blocks of block_size right-hand sides), and every process returns
  /// all of them (the columns are summed over the group). Every process factorizes the whole
  /// matrix: sharing divides the time of the solves, not the memory of the factor. Anchored
  /// objects: the result equals one process's to round-off; unconstrained: to MINRES's
  /// tolerance, since the blocks are formed from each process's share. Progress counts the
  /// group's work at the end of each block; a failure or cancel on one process ends every
  /// process (WorkGroup).
  WorkGroup* group = nullptr;
  /// Makes the factorization of K (anchored) or of MINRES's preconditioner K − σM (free), on
  /// the free dofs; empty: CHOLMOD on every process. A collective factorization (its factor
  /// distributed over the processes of `group`, e.g. khz::mpi::MumpsFactorization::factorize())
  /// needs every process of the group in every solve: each process then solves every block,
  /// and the group shares the factor's memory and the work inside each solve instead.
  Factorize factorize;
};

/// The derivatives Φᵢⱼ, unnormalized, on the full dofs (zero at fixed vertices).
struct ModalDerivatives {
  /// 3n × pairs.size(); column c is Φ for pairs[c].
  Eigen::MatrixXd vectors;
  /// (i, j), 0-based columns of LinearModes::modes. Anchored objects: every i ≤ j
  /// (k(k+1)/2 pairs, Φᵢⱼ = Φⱼᵢ); unconstrained objects: every ordered pair (k² pairs), since
  /// the inertia terms make Φᵢⱼ ≠ Φⱼᵢ.
  std::vector<std::array<int, 2>> pairs;
  /// Unconstrained objects: the most MINRES iterations one block needed; 0 otherwise.
  int max_minres_iterations = 0;
};

/// Modal derivatives of `modes` (computed for `model` by compute_linear_modes).
///
/// Anchored: K Φᵢⱼ = −(H : Ψⱼ) Ψᵢ (eq. 2.47) with one Cholesky factorization of K on the free
/// dofs and the right-hand sides solved in blocks. Unconstrained: (K − λᵢM) Φᵢⱼ =
/// (MΨᵢΨᵢᵀ − I)(H : Ψⱼ)Ψᵢ (eq. 2.60) with Ψᵢᵀ M Φᵢⱼ = 0: exactly along the rigid and computed
/// modes (K − λᵢM is indefinite or singular along them), and by MINRES in their M-orthogonal
/// complement, preconditioned with a Cholesky factorization of K − σM (σ < 0) and deflated by
/// Ritz vectors of the next modes (32 more solves), blocks of right-hand sides in lockstep.
///
/// @throws Error if `modes` does not fit the model or options are invalid; SolverError if a
///         factorization fails or MINRES does not converge (for an unconstrained object, e.g.
///         when its last modes have an equal-eigenvalue twin past the k computed: eq. 2.60 has
///         no solution along it); Cancelled.
KHZ_REDUCED_API ModalDerivatives compute_modal_derivatives(
    const FemModel& model, const LinearModes& modes, const ModalDerivativesOptions& options = {});

}  // namespace khz::reduced
