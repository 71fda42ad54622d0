// The 6×6 equilibrium solve of thesis §4.10 against systems built from known singular vectors,
// and against LU (eq. 4.1–4.2) where the system is regular.

#include <khz/haptic/coupling/equilibrium.hpp>

#include <gtest/gtest.h>

#include <Eigen/QR>

#include <cstdio>
#include <random>

namespace khz::haptic {
namespace {

Matrix6d random_orthogonal(std::mt19937& random) {
  std::normal_distribution<double> normal;
  const Matrix6d m = Matrix6d::NullaryExpr([&] { return normal(random); });
  return Eigen::HouseholderQR<Matrix6d>(m).householderQ();
}

Vector6d random_vector(std::mt19937& random) {
  std::normal_distribution<double> normal;
  return Vector6d::NullaryExpr([&] { return normal(random); });
}

// A = U diag(σ) Vᵀ with σ in [1, 100] · scale: regular, condition ≤ 100.
TEST(EquilibriumSolve, SvdEqualsLuOnRegularSystems) {
  std::mt19937 random(1234);
  std::uniform_real_distribution<double> spread(0.0, 2.0);
  double worst = 0.0;
  for (int trial = 0; trial < 200; ++trial) {
    Vector6d sigma;
    for (int i = 0; i < 6; ++i) sigma[i] = std::pow(10.0, spread(random));
    const double scale = std::pow(10.0, 4.0 * spread(random) - 2.0);
    const Matrix6d a = scale * random_orthogonal(random) * sigma.asDiagonal() *
                       random_orthogonal(random).transpose();
    const Vector6d b = random_vector(random);
    const Vector6d target = random_vector(random);  // must not matter
    const EquilibriumSolution svd = solve_equilibrium(a, b, target, 1e-3);
    const Vector6d lu = solve_equilibrium_lu(a, b);
    EXPECT_EQ(svd.degenerate_dimension, 0);
    const double error = (svd.step - lu).norm() / lu.norm();
    worst = std::max(worst, error);
    EXPECT_LE(error, 1e-12) << "trial " << trial;
    EXPECT_LE((a * svd.step - b).norm(), 1e-12 * b.norm()) << "trial " << trial;
  }
  char text[32];
  std::snprintf(text, sizeof text, "%.3g", worst);
  RecordProperty("worst_relative_difference", text);
}

// A = U diag(σ) Vᵀ with the last `dimension` singular values below ε σ₁ (tiny, or exactly 0):
// the solution is V_nd Σ_nd⁻¹ U_ndᵀ b + V_d V_dᵀ target (eq. 4.41), computed here from the U, V
// the system was built with. The kept singular values span a factor 100 (error ≲ 100 ε_mach).
TEST(EquilibriumSolve, DegenerateDirectionsSnapToTheTarget) {
  std::mt19937 random(99);
  for (int dimension = 1; dimension <= 6; ++dimension) {
    for (const double small : {0.0, 1e-9, 5e-4}) {
      const Matrix6d u = random_orthogonal(random);
      const Matrix6d v = random_orthogonal(random);
      Vector6d sigma;
      sigma << 500.0, 200.0, 80.0, 30.0, 12.0, 5.0;  // all ≥ ε σ₁ = 0.5
      for (int i = 6 - dimension; i < 6; ++i) sigma[i] = small * 500.0 * (1.0 - 0.1 * i);
      if (dimension == 6) sigma.setZero();  // A = 0: only the target is left
      const Matrix6d a = u * sigma.asDiagonal() * v.transpose();
      const Vector6d b = 10.0 * random_vector(random);
      const Vector6d target = random_vector(random);

      Vector6d expected = Vector6d::Zero();
      for (int i = 0; i < 6; ++i) {
        const bool degenerate = i >= 6 - dimension;
        expected += (degenerate ? v.col(i).dot(target) : u.col(i).dot(b) / sigma[i]) * v.col(i);
      }

      const EquilibriumSolution solution = solve_equilibrium(a, b, target, 1e-3);
      EXPECT_EQ(solution.degenerate_dimension, dimension) << "small " << small;
      EXPECT_LE((solution.step - expected).norm(), 1e-13 * expected.norm())
          << "dimension " << dimension << " small " << small;
      // Bounded: no larger than the regular part's solution and the target together.
      EXPECT_LE(solution.step.norm(), b.norm() / 5.0 + target.norm());
      // LU, on the same system, explodes (truncated SVD would drop the target's part).
      if (small == 1e-9 && dimension < 6) {
        EXPECT_GT(solve_equilibrium_lu(a, b).norm(), 1e6 * solution.step.norm());
      }
    }
  }
}

// The threshold is relative: σᵢ ≥ ε σ₁ is kept, σᵢ < ε σ₁ snaps.
TEST(EquilibriumSolve, ThresholdIsRelativeToTheLargestSingularValue) {
  std::mt19937 random(5);
  const Matrix6d u = random_orthogonal(random);
  const Matrix6d v = random_orthogonal(random);
  for (const double scale : {1e-6, 1.0, 1e6}) {
    Vector6d sigma;
    sigma << 1000.0, 500.0, 100.0, 10.0, 1.01, 0.99;
    const Matrix6d a = scale * u * sigma.asDiagonal() * v.transpose();
    EXPECT_EQ(solve_equilibrium(a, random_vector(random), random_vector(random), 1e-3)
                  .degenerate_dimension,
              1)
        << scale;
    EXPECT_EQ(solve_equilibrium(a, random_vector(random), random_vector(random), 2e-3)
                  .degenerate_dimension,
              2)
        << scale;
  }
}

}  // namespace
}  // namespace khz::haptic
