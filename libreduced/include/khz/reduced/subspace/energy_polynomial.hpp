#pragma once
// The reduced strain energy of a linear-material model: a quartic polynomial in q (thesis §2.6).

#include <khz/reduced/export.hpp>

#include <Eigen/Core>

namespace khz::reduced {

/// The strain energy of a reduced StVK or general linear-material model (thesis §2.6), exactly a
/// polynomial of degree four in the reduced coordinates q ∈ Rʳ:
///
///   E(q) = ½ qᵀ K q + Σ_{a≤b≤c} C_abc q_a q_b q_c + Σ_{a≤b≤c≤d} T_abcd q_a q_b q_c q_d.
///
/// Its gradient is the reduced internal force R̃(q) = UᵀR(Uq), a cubic (eq. 2.26–2.27: P^i is
/// column i of K; Q and S are the derivatives of the C and T terms), and its Hessian the reduced
/// tangent stiffness K̃(q) (eq. 2.32); K = K̃(0). Storing the energy instead of R̃'s vector
/// coefficients keeps every coefficient once: C(r+3, 4) quartic numbers instead of r·C(r+2, 3).
///
/// Coefficients of monomials are stored in colexicographic order: tuples (a ≤ b ≤ c) ordered by
/// c, then b, then a, so that the polynomial in the first r' coordinates is a prefix (§2.11):
/// index(a, b, c) = C(c+2, 3) + C(b+1, 2) + a and index(a, b, c, d) = C(d+3, 4) + index(a, b, c).
struct KHZ_REDUCED_API EnergyPolynomial {
  Eigen::MatrixXd quadratic;  ///< K, r×r symmetric (N·m per unit q²).
  Eigen::VectorXd cubic;      ///< C_abc, cubic_size(r) entries in colexicographic order.
  Eigen::VectorXd quartic;    ///< T_abcd, quartic_size(r) entries in colexicographic order.

  /// A zero polynomial in r coordinates.
  static EnergyPolynomial zero(Eigen::Index r);
  /// Number of cubic monomials in r variables, C(r+2, 3).
  static Eigen::Index cubic_size(Eigen::Index r) noexcept;
  /// Number of quartic monomials in r variables, C(r+3, 4).
  static Eigen::Index quartic_size(Eigen::Index r) noexcept;
  /// Position of monomial q_a q_b q_c (a ≤ b ≤ c) in `cubic`.
  static Eigen::Index cubic_index(int a, int b, int c) noexcept;
  /// Position of monomial q_a q_b q_c q_d (a ≤ b ≤ c ≤ d) in `quartic`.
  static Eigen::Index quartic_index(int a, int b, int c, int d) noexcept;

  /// r, the number of coordinates. @throws nothing; sizes are checked by validate().
  Eigen::Index dimension() const noexcept { return quadratic.rows(); }
  /// @throws Error unless the sizes agree with r = quadratic.rows(), K is square and symmetric
  ///         (to 1e-12 relative) and every coefficient is finite.
  void validate() const;
  /// The polynomial restricted to the first r' ≤ r coordinates (the others held at zero):
  /// prefixes of the coefficient arrays (§2.11). @throws Error unless 0 ≤ r' ≤ r.
  EnergyPolynomial truncated(Eigen::Index r) const;
  /// this += weight · other (same r), e.g. to sum material groups weighted by λ and μ (§2.11).
  /// @throws Error if the dimensions differ.
  void add_scaled(double weight, const EnergyPolynomial& other);

  /// E(q), evaluated monomial by monomial: a slow reference for tests and tools, not for time
  /// stepping (use PolynomialForces). @throws Error if q does not have r entries.
  double energy(const Eigen::VectorXd& q) const;
};

}  // namespace khz::reduced
