#pragma once
// Random reduced energy polynomials for the evaluator tests and benchmarks (header-only and free
// of GoogleTest, so benchmarks can use it too).

#include <khz/reduced/subspace/energy_polynomial.hpp>

#include <Eigen/Core>

#include <random>

namespace khz::test {

/// A polynomial in r coordinates with cubic and quartic coefficients uniform in [−1, 1] and
/// K = AᵀA + I (A uniform in [−1, 1]), so the rest state is stable; the same for the same seed.
inline reduced::EnergyPolynomial random_polynomial(Eigen::Index r, unsigned seed) {
  std::mt19937_64 random(seed);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  reduced::EnergyPolynomial p = reduced::EnergyPolynomial::zero(r);
  Eigen::MatrixXd a(r, r);
  for (Eigen::Index k = 0; k < a.size(); ++k) a.data()[k] = uniform(random);
  p.quadratic = a.transpose() * a + Eigen::MatrixXd::Identity(r, r);
  for (double& c : p.cubic) c = uniform(random);
  for (double& t : p.quartic) t = uniform(random);
  return p;
}

}  // namespace khz::test
