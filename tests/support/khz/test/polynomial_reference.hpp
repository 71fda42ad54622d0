#pragma once
// Gradient and Hessian of an EnergyPolynomial by differentiating its monomials one by one: an
// independent, slow reference for the reduced force evaluators.

#include <khz/reduced/subspace/energy_polynomial.hpp>

#include <Eigen/Core>

#include <array>

namespace khz::test {

/// Adds coefficient · Π q_{index} to the gradient and Hessian by the product rule over the
/// monomial's factor positions (correct for repeated indices too).
template <std::size_t N>
void add_monomial(double coefficient, const std::array<int, N>& index, const Eigen::VectorXd& q,
                  Eigen::VectorXd& gradient, Eigen::MatrixXd& hessian) {
  for (std::size_t i = 0; i < N; ++i) {
    double others = coefficient;
    for (std::size_t k = 0; k < N; ++k) {
      if (k != i) others *= q[index[k]];
    }
    gradient[index[i]] += others;
    for (std::size_t j = 0; j < N; ++j) {
      if (j == i) continue;
      double rest = coefficient;
      for (std::size_t k = 0; k < N; ++k) {
        if (k != i && k != j) rest *= q[index[k]];
      }
      hessian(index[i], index[j]) += rest;
    }
  }
}

/// ∇E(q) and ∇²E(q) of `polynomial`.
inline void reference_derivatives(const reduced::EnergyPolynomial& polynomial,
                                  const Eigen::VectorXd& q, Eigen::VectorXd& gradient,
                                  Eigen::MatrixXd& hessian) {
  const int r = static_cast<int>(polynomial.dimension());
  gradient = polynomial.quadratic * q;
  hessian = polynomial.quadratic;
  for (int c = 0; c < r; ++c) {
    for (int b = 0; b <= c; ++b) {
      for (int a = 0; a <= b; ++a) {
        add_monomial<3>(polynomial.cubic[reduced::EnergyPolynomial::cubic_index(a, b, c)],
                        {a, b, c}, q, gradient, hessian);
        for (int d = c; d < r; ++d) {
          add_monomial<4>(polynomial.quartic[reduced::EnergyPolynomial::quartic_index(a, b, c, d)],
                          {a, b, c, d}, q, gradient, hessian);
        }
      }
    }
  }
}

}  // namespace khz::test
