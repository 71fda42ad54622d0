#pragma once
// Exact reduced forces, tangent stiffness and energy from the precomputed energy polynomial, at
// haptic rates (thesis §2.6.4).

#include <khz/reduced/export.hpp>
#include <khz/reduced/subspace/energy_polynomial.hpp>
#include <khz/reduced/subspace/reduced_forces.hpp>

#include <Eigen/Core>

#include <cstddef>
#include <memory>

namespace khz::reduced {

/// R̃(q) = ∇E(q), K̃(q) = ∇²E(q) and E(q) of a reduced linear-material model whose strain energy
/// is the quartic EnergyPolynomial E (thesis §2.6, eq. 2.26–2.32, evaluated as in §2.6.4),
/// exactly, in double precision. Units are those of the polynomial: E in J, R̃ in N·(m per unit
/// q), K̃ in N·(m per unit q)².
///
/// Layout (DESIGN.md §3, "store them in the order the evaluation reads them"): the coefficients
/// are copied once into a private order made for streaming. Appending the constant coordinate
/// q_r = 1 turns E into one homogeneous quartic Ê in n = r + 1 coordinates (the thesis's
/// homogenization), whose monomials are grouped by their two largest indices (c, d) into small
/// symmetric matrices X_cd over the two smallest. Each X_cd is stored column by column in 8×8
/// tiles, off-diagonal tiles once and diagonal tiles in full, so that one pass computes every
/// product X_cd q with 8-lane FMAs plus one transposed horizontal sum per eight columns (AVX-512
/// where the build targets it, a portable version otherwise); the Hessian follows from those
/// products and X_cd itself. coefficient_bytes() is 1.7× (r = 15) to 1.2× (r = 60) the
/// C(r+3, 4) + C(r+2, 3) + r(r+1)/2 canonical coefficients. Euler's identity for the homogeneous
/// Ê gives the force from the Hessian Ĥ for O(r²) more: R̃ = ⅓ (Ĥ q̂)[0..r). For large r an
/// evaluation runs at the speed of streaming the coefficients from memory.
///
/// Not safe to use from two threads at once (it owns its workspace); evaluations are
/// single-threaded, noexcept and allocation-free. A moved-from model may only be destroyed or
/// assigned to.
class KHZ_REDUCED_API PolynomialForces final : public ReducedForceModel {
 public:
  /// Copies `polynomial` into the streaming layout (allocates; O(r⁴)).
  /// @throws Error if the polynomial has no coordinates (r = 0) or polynomial.validate() fails
  ///         (sizes, non-finite or asymmetric coefficients).
  explicit PolynomialForces(const EnergyPolynomial& polynomial);
  ~PolynomialForces() override;
  PolynomialForces(PolynomialForces&&) noexcept;
  PolynomialForces& operator=(PolynomialForces&&) noexcept;

  /// Replaces the coefficients by those of `polynomial`, in the same dimension, without
  /// allocating: e.g. after re-summing material groups weighted by new λ and μ (thesis §2.11).
  /// @throws Error if polynomial.validate() fails or its dimension differs from dimension();
  ///         the old coefficients are then kept.
  void set_polynomial(const EnergyPolynomial& polynomial);

  Eigen::Index dimension() const noexcept override;
  void evaluate(const Eigen::Ref<const Eigen::VectorXd>& q, Eigen::Ref<Eigen::VectorXd> forces,
                Eigen::Ref<Eigen::MatrixXd> stiffness) noexcept override;
  /// R̃(q) alone: the same pass over the coefficients with the block products only (about ⅔ of
  /// the time of evaluate() for r ≤ 30, the same when memory-bound).
  void evaluate_forces(const Eigen::Ref<const Eigen::VectorXd>& q,
                       Eigen::Ref<Eigen::VectorXd> forces) noexcept override;
  /// E(q): one FMA per eight streamed coefficients.
  double energy(const Eigen::Ref<const Eigen::VectorXd>& q) noexcept override;

  /// Bytes of coefficients one evaluation streams (the memory traffic that bounds it for large r).
  std::size_t coefficient_bytes() const noexcept;

 private:
  struct State;
  std::unique_ptr<State> m_state;
};

}  // namespace khz::reduced
