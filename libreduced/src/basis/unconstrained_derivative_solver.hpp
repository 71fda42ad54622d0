#pragma once
// The linear solve of the unconstrained modal derivatives (thesis §2.8.7, eq. 2.60):
// (K − λᵢM) Φ = b with Ψᵢᵀ M Φ = 0, by MINRES deflated twice.
//
// K − λᵢM is singular along Ψᵢ and indefinite: negative along the rigid motions and the modes
// below λᵢ. Those directions are known (the rigid modes and the computed modes V, M-orthonormal,
// eigenvalues μ), so the solution splits:
//   - along V, exactly: Vₘᵀ M Φ = Vₘᵀ b / (μₘ − λᵢ); zero for the modes whose eigenvalue equals
//     λᵢ to 1e-6 (Ψᵢ, and its twins on symmetric shapes, along which the derivative is
//     ambiguous);
//   - in the M-orthogonal complement of V (projector Q = I − V VᵀM), where A = Qᵀ(K − λᵢM)Q is
//     positive definite, by MINRES preconditioned with Q (K − σM)⁻¹ Qᵀ.
// Removing V takes away the preconditioned operator's negative eigenvalues (−λᵢ/|σ| along the
// rigid motions, |σ| tiny). What then slows MINRES is the modes just above the computed ones,
// where (μ − λᵢ)/(μ − σ) is smallest, most for the last modes: 16 iterations for i = 10 against
// 6 for i = 1 on a 23k-vertex mesh. A second, Galerkin deflation (Nicolaides 1987; Saad, Yeung,
// Erhel & Guyomarc'h 2000) removes Ritz approximations W of those modes: MINRES solves
// (A − AW E⁻¹ WᵀA) x = (I − AW E⁻¹ Wᵀ) b, E = WᵀAW, and x + W E⁻¹ Wᵀ(b − A x) solves A Φ = b
// exactly, however rough W is; roughness only costs iterations.

#include "block_minres.hpp"
#include "modal_problem.hpp"
#include "shifted_stiffness.hpp"

#include <khz/reduced/basis/linear_modes.hpp>
#include <khz/reduced/solvers/symmetric_factorization.hpp>

#include <Eigen/Core>

#include <functional>
#include <vector>

namespace khz::reduced::detail {

/// Solves eq. 2.60 for blocks of right-hand sides, each with its own λᵢ.
class UnconstrainedDerivativeSolver {
 public:
  /// Keeps a reference to `preconditioner`; reads `problem` and `modes` only here. Computes the
  /// Ritz vectors W with a few solves of `preconditioner` (K − σM) on a block Krylov space started
  /// from a fixed pseudo-random block, so every process of a group computes the same W (and calls a
  /// collective factorization the same number of times).
  /// @throws SolverError if a solve fails.
  UnconstrainedDerivativeSolver(const ModalProblem& problem, const LinearModes& modes,
                                SymmetricFactorization& preconditioner);

  /// Φ, n × m: column c solves (K − λ_c M) Φ_c = b_c with Φ_c M-orthogonal to the modes whose
  /// eigenvalue equals λ_c. The part of b_c along those modes (Ψᵀ b_c) is dropped, as eq.
  /// 2.60's (MΨᵢΨᵢᵀ − I) does, so b_c may be −(H : Ψⱼ)Ψᵢ itself. `check` is called every MINRES
  /// iteration (it may throw to cancel); `report` says how MINRES did, and the caller decides what
  /// non-convergence means.
  Eigen::MatrixXd solve(const Eigen::MatrixXd& b, const Eigen::VectorXd& lambda, double tolerance,
                        int max_iterations, const std::function<void()>& check,
                        MinresReport& report) const;

 private:
  /// x ← Q x = x − V (MV)ᵀ x: the complement's part of displacements.
  void project_displacements(Eigen::MatrixXd& x) const;
  /// y ← Qᵀ y = y − MV Vᵀ y: the part of forces that does work in the complement.
  void project_forces(Eigen::MatrixXd& y) const;
  /// y = A x = Qᵀ(K − λ_c M) x for x in the range of Q.
  void apply_complement(const Eigen::MatrixXd& x, const Eigen::VectorXd& lambda,
                        Eigen::MatrixXd& y) const;
  /// E⁻¹ Wᵀ y, column c with E = diag(θ) − λ_c I.
  Eigen::MatrixXd coarse_solve(const Eigen::MatrixXd& y, const Eigen::VectorXd& lambda) const;
  /// y ← y − A W h, column c of A W being Qᵀ(K − λ_c M) W.
  void subtract_coarse(const Eigen::MatrixXd& h, const Eigen::VectorXd& lambda,
                       Eigen::MatrixXd& y) const;
  /// The Ritz vectors of K w = θ M w in the complement of V, lowest first.
  void compute_ritz_vectors(const ModalProblem& problem);

  SymmetricFactorization& m_preconditioner;
  ShiftedStiffness m_shifted_stiffness;
  Eigen::MatrixXd m_v;            ///< V = [rigid modes, Ψ]
  Eigen::MatrixXd m_mass_v;       ///< MV
  Eigen::VectorXd m_eigenvalues;  ///< μ: 0 for the rigid modes, then λ
  Eigen::MatrixXd m_w;            ///< W, M-orthonormal, M-orthogonal to V
  Eigen::MatrixXd m_mass_w;       ///< MW
  Eigen::MatrixXd m_stiffness_w;  ///< Qᵀ K W
  Eigen::VectorXd m_ritz_values;  ///< θ = diag(WᵀKW)
};

}  // namespace khz::reduced::detail
