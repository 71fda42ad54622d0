#pragma once
// The linearized static equilibrium of the simulation object (thesis eq. 4.1–4.2) and its solve
// with degenerate-rank handling (§4.10).

#include <khz/contact/query/contact_wrench.hpp>
#include <khz/haptic/coupling/coupling_wrench.hpp>
#include <khz/haptic/export.hpp>

#include <Eigen/Core>

namespace khz::haptic {

using Vector6d = Eigen::Matrix<double, 6, 1>;
using Matrix6d = Eigen::Matrix<double, 6, 6>;

/// The net force and torque on the simulation object under a small motion (Δx, Δω):
///   [F_net; T_net](Δx, Δω) ≈ net_wrench + jacobian [Δx; Δω]      (eq. 4.1–4.2)
/// Rows: force (N), torque (N·m); columns: Δx (m), Δω (rad, world axes about the grasp point).
struct EquilibriumSystem {
  /// [∂F_VC/∂x + ∂F_C/∂x, ∂F_C/∂ω; ∂T_C/∂x, ∂T_VC/∂ω + ∂T_C/∂ω] (∂F_VC/∂ω = ∂T_VC/∂x = 0).
  Matrix6d jacobian = Matrix6d::Zero();
  /// [F_VC + F_C; T_VC + T_C].
  Vector6d net_wrench = Vector6d::Zero();
};

/// Adds the coupling and the contact terms. The contact query supplies only its force, torque
/// and four gradients here; it must have been evaluated at the simulation pose the coupling
/// wrench was.
KHZ_HAPTIC_API EquilibriumSystem equilibrium_system(const CouplingWrench& coupling,
                                                    const contact::ContactWrench& contact) noexcept;

/// What the degenerate-rank solve found.
struct EquilibriumSolution {
  /// x = x_nd + x_d.
  Vector6d step = Vector6d::Zero();
  /// Columns of V_d: singular values below ε σ₁ (all six if σ₁ = 0).
  int degenerate_dimension = 0;
};

/// Solves A x = b by §4.10: with A = U Σ Vᵀ (σ₁ ≥ … ≥ σ₆ ≥ 0) split into the columns whose
/// σᵢ ≥ ε σ₁ (V_nd, U_nd) and the rest (V_d),
///   x_nd = V_nd Σ_nd⁻¹ U_ndᵀ b          (the minimum-norm solution within span V_nd)
///   x_d  = V_d V_dᵀ target              (eq. 4.41: in the directions the system does not
///                                        resist, move to the manipulandum)
/// and x = x_nd + x_d. Not truncated SVD (x_d = 0) and not Tikhonov. The SVD is by one-sided
/// Jacobi rotations (~1 µs). Allocates nothing; with a finite A, b and target the result is
/// finite.
/// @param epsilon ε of §4.10, relative to σ₁ (the thesis uses 1e-3).
/// @param target the pose difference to snap to: [x_m − x_s; rotation vector of
///        toPositiveHemisphere(q_m q_s⁻¹)] for the virtual coupling.
KHZ_HAPTIC_API EquilibriumSolution solve_equilibrium(const Matrix6d& a, const Vector6d& b,
                                                     const Vector6d& target,
                                                     double epsilon) noexcept;

/// Solves A x = b by LU with partial pivoting, as the thesis did before §4.10 (eq. 4.1–4.2);
/// not finite for a singular A. For comparison.
KHZ_HAPTIC_API Vector6d solve_equilibrium_lu(const Matrix6d& a, const Vector6d& b) noexcept;

}  // namespace khz::haptic
