#include <khz/reduced/errors.hpp>
#include <khz/reduced/subspace/energy_polynomial.hpp>
#include <khz/reduced/subspace/polynomial_forces.hpp>
#include <khz/test/allocation_probe.hpp>
#include <khz/test/random_polynomial.hpp>

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <limits>
#include <random>
#include <string>

namespace khz::reduced {
namespace {

/// Dimensions on both sides of the kernels' 8-lane tiles: with n = r + 1 homogenized
/// coordinates, r = 7 and 15 fill one and two tiles, and r = 31 needs four.
using test::random_polynomial;

constexpr std::array kDimensions{1, 2, 3, 7, 8, 9, 15, 16, 17, 31};

/// The brief's accuracy bound for the exact evaluations; measured errors are below 2e-14.
constexpr double kExact = 1e-12;

Eigen::VectorXd random_q(Eigen::Index r, unsigned seed) {
  std::mt19937_64 random(seed);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  Eigen::VectorXd q(r);
  for (double& x : q) x = uniform(random);
  return q;
}

/// R̃, K̃ and E by differentiating every colexicographic monomial of the polynomial directly.
struct Reference {
  Eigen::VectorXd forces;
  Eigen::MatrixXd stiffness;
  double energy = 0.0;
};

/// Adds coefficient · Π q[index] and its first and second derivatives.
template <std::size_t N>
void add_monomial(double coefficient, const std::array<int, N>& index, const Eigen::VectorXd& q,
                  Reference& out) {
  const auto product_except = [&](std::size_t skip1, std::size_t skip2) {
    double product = coefficient;
    for (std::size_t k = 0; k < N; ++k) {
      if (k != skip1 && k != skip2) product *= q[index[k]];
    }
    return product;
  };
  out.energy += product_except(N, N);
  for (std::size_t k = 0; k < N; ++k) {
    out.forces[index[k]] += product_except(k, N);
    for (std::size_t l = 0; l < N; ++l) {
      if (l != k) out.stiffness(index[k], index[l]) += product_except(k, l);
    }
  }
}

Reference reference(const EnergyPolynomial& p, const Eigen::VectorXd& q) {
  const auto r = static_cast<int>(p.dimension());
  Reference out{p.quadratic * q, p.quadratic, 0.5 * q.dot(p.quadratic * q)};
  for (int c = 0; c < r; ++c) {
    for (int b = 0; b <= c; ++b) {
      for (int a = 0; a <= b; ++a) {
        add_monomial(p.cubic[EnergyPolynomial::cubic_index(a, b, c)], std::array{a, b, c}, q, out);
      }
    }
  }
  for (int d = 0; d < r; ++d) {
    for (int c = 0; c <= d; ++c) {
      for (int b = 0; b <= c; ++b) {
        for (int a = 0; a <= b; ++a) {
          add_monomial(p.quartic[EnergyPolynomial::quartic_index(a, b, c, d)],
                       std::array{a, b, c, d}, q, out);
        }
      }
    }
  }
  return out;
}

double relative_error(const Eigen::MatrixXd& value, const Eigen::MatrixXd& expected) {
  return (value - expected).norm() / expected.norm();
}

struct Evaluation {
  Eigen::VectorXd forces;
  Eigen::MatrixXd stiffness;
  Eigen::VectorXd forces_only;
  double energy = 0.0;
};

Evaluation evaluate(PolynomialForces& model, const Eigen::VectorXd& q) {
  const Eigen::Index r = model.dimension();
  Evaluation out{Eigen::VectorXd(r), Eigen::MatrixXd(r, r), Eigen::VectorXd(r), 0.0};
  model.evaluate(q, out.forces, out.stiffness);
  model.evaluate_forces(q, out.forces_only);
  out.energy = model.energy(q);
  return out;
}

TEST(PolynomialForces, MatchesDirectDifferentiationOfTheMonomials) {
  for (const int r : kDimensions) {
    SCOPED_TRACE("r = " + std::to_string(r));
    const EnergyPolynomial p = random_polynomial(r, 10u + static_cast<unsigned>(r));
    PolynomialForces model(p);
    EXPECT_EQ(model.dimension(), r);
    for (const double scale : {0.01, 1.0}) {
      const Eigen::VectorXd q = scale * random_q(r, 100u + static_cast<unsigned>(r));
      const Reference expected = reference(p, q);
      const Evaluation got = evaluate(model, q);
      EXPECT_LE(relative_error(got.forces, expected.forces), kExact);
      EXPECT_LE(relative_error(got.forces_only, expected.forces), kExact);
      EXPECT_LE(relative_error(got.stiffness, expected.stiffness), kExact);
      EXPECT_NEAR(got.energy, expected.energy, kExact * std::abs(expected.energy));
      EXPECT_TRUE(got.stiffness == got.stiffness.transpose());
    }
  }
}

TEST(PolynomialForces, WorksBeyondRegisterTiles) {
  // n = 65 homogenized coordinates: the last slice has 9 tiles of 8 and takes the scratch path.
  const int r = 64;
  const EnergyPolynomial p = random_polynomial(r, 3);
  PolynomialForces model(p);
  const Eigen::VectorXd q = random_q(r, 4);
  const Reference expected = reference(p, q);
  const Evaluation got = evaluate(model, q);
  EXPECT_LE(relative_error(got.forces, expected.forces), kExact);
  EXPECT_LE(relative_error(got.forces_only, expected.forces), kExact);
  EXPECT_LE(relative_error(got.stiffness, expected.stiffness), kExact);
  EXPECT_NEAR(got.energy, expected.energy, kExact * std::abs(expected.energy));
}

TEST(PolynomialForces, WritesIntoBlocksOfLargerMatrices) {
  // The stiffness is written tile by tile through the Ref's outer stride, and only r×r of it.
  const int r = 9;
  PolynomialForces model(random_polynomial(r, 5));
  const Eigen::VectorXd q = random_q(r, 6);
  const Evaluation expected = evaluate(model, q);
  const double sentinel = -12345.0;
  Eigen::MatrixXd big = Eigen::MatrixXd::Constant(r + 3, r + 2, sentinel);
  Eigen::VectorXd forces = Eigen::VectorXd::Constant(r + 1, sentinel);
  model.evaluate(q, forces.head(r), big.block(1, 1, r, r));
  EXPECT_TRUE(big.block(1, 1, r, r) == expected.stiffness);
  EXPECT_TRUE(forces.head(r) == expected.forces);
  EXPECT_EQ(forces[r], sentinel);
  big.block(1, 1, r, r).setConstant(sentinel);
  EXPECT_TRUE((big.array() == sentinel).all());
}

TEST(PolynomialForces, StiffnessAndForcesAreDerivativesByFiniteDifferences) {
  // Independent of the monomial reference: K̃ against central differences of R̃, and R̃ against
  // central differences of EnergyPolynomial::energy. R̃ is cubic and E quartic, so the
  // truncation error is h²/6 times a third derivative: measured 2e-9 to 1e-8 relative here.
  const double h = 1e-4;
  for (const int r : {3, 9, 17}) {
    SCOPED_TRACE("r = " + std::to_string(r));
    const EnergyPolynomial p = random_polynomial(r, 20u + static_cast<unsigned>(r));
    PolynomialForces model(p);
    const Eigen::VectorXd q = random_q(r, 200u + static_cast<unsigned>(r));
    const Evaluation got = evaluate(model, q);
    Eigen::MatrixXd stiffness_fd(r, r);
    Eigen::VectorXd forces_fd(r), plus(r), minus(r);
    for (int j = 0; j < r; ++j) {
      Eigen::VectorXd step = Eigen::VectorXd::Zero(r);
      step[j] = h;
      model.evaluate_forces(q + step, plus);
      model.evaluate_forces(q - step, minus);
      stiffness_fd.col(j) = (plus - minus) / (2 * h);
      forces_fd[j] = (p.energy(q + step) - p.energy(q - step)) / (2 * h);
    }
    EXPECT_LE(relative_error(got.stiffness, stiffness_fd), 1e-7);
    EXPECT_LE(relative_error(got.forces, forces_fd), 1e-7);
    EXPECT_NEAR(got.energy, p.energy(q), kExact * std::abs(p.energy(q)));
  }
}

TEST(PolynomialForces, SetPolynomialMatchesAFreshModelWithoutAllocating) {
  for (const int r : {7, 17}) {
    SCOPED_TRACE("r = " + std::to_string(r));
    PolynomialForces model(random_polynomial(r, 1));
    const EnergyPolynomial replacement = random_polynomial(r, 2);
    test::allocation_count = 0;
    model.set_polynomial(replacement);
    EXPECT_EQ(test::allocation_count, 0u);

    PolynomialForces fresh(replacement);
    const Eigen::VectorXd q = random_q(r, 5);
    const Evaluation got = evaluate(model, q);
    const Evaluation expected = evaluate(fresh, q);
    EXPECT_TRUE(got.forces == expected.forces);
    EXPECT_TRUE(got.stiffness == expected.stiffness);
    EXPECT_TRUE(got.forces_only == expected.forces_only);
    EXPECT_EQ(got.energy, expected.energy);
  }
}

TEST(PolynomialForces, EvaluationsAllocateNothing) {
  if (!test::allocation_count_sees_malloc) {
    GTEST_LOG_(INFO) << "counting operator new only (sanitized build)";
  }
  for (const int r : {1, 9, 31}) {
    PolynomialForces model(random_polynomial(r, 7));
    const Eigen::VectorXd q = random_q(r, 8);
    Eigen::VectorXd forces(r);
    Eigen::MatrixXd stiffness(r, r);
    test::allocation_count = 0;
    model.evaluate(q, forces, stiffness);
    model.evaluate_forces(q, forces);
    const double energy = model.energy(q);
    EXPECT_EQ(test::allocation_count, 0u) << "r = " << r;
    EXPECT_TRUE(std::isfinite(energy));
  }
}

/// The message of the Error `action` throws, or "" (a test failure) if it throws none.
template <typename Action>
std::string error_message(Action&& action) {
  try {
    action();
  } catch (const Error& error) {
    return error.what();
  }
  ADD_FAILURE() << "no Error thrown";
  return "";
}

TEST(PolynomialForces, RejectsInvalidPolynomials) {
  EXPECT_NE(error_message([] { PolynomialForces{EnergyPolynomial::zero(0)}; }).find("coordinates"),
            std::string::npos);

  EnergyPolynomial short_quartic = random_polynomial(4, 1);
  short_quartic.quartic.conservativeResize(short_quartic.quartic.size() - 1);
  EXPECT_NE(error_message([&] { PolynomialForces{short_quartic}; }).find("quartic"),
            std::string::npos);

  EnergyPolynomial long_cubic = random_polynomial(4, 1);
  long_cubic.cubic.conservativeResize(long_cubic.cubic.size() + 1);
  EXPECT_NE(error_message([&] { PolynomialForces{long_cubic}; }).find("cubic"), std::string::npos);

  EnergyPolynomial not_square = random_polynomial(4, 1);
  not_square.quadratic.conservativeResize(4, 3);
  EXPECT_NE(error_message([&] { PolynomialForces{not_square}; }).find("square"), std::string::npos);

  EnergyPolynomial nan = random_polynomial(4, 1);
  nan.quartic[3] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_NE(error_message([&] { PolynomialForces{nan}; }).find("finite"), std::string::npos);

  PolynomialForces model(random_polynomial(4, 1));
  EXPECT_NE(error_message([&] { model.set_polynomial(nan); }).find("finite"), std::string::npos);
}

TEST(PolynomialForces, SetPolynomialRejectsADimensionChange) {
  PolynomialForces model(random_polynomial(5, 1));
  const Eigen::VectorXd q = random_q(5, 2);
  const double before = model.energy(q);
  const std::string message = error_message([&] { model.set_polynomial(random_polynomial(6, 1)); });
  EXPECT_NE(message.find("6 coordinates"), std::string::npos) << message;
  EXPECT_EQ(model.energy(q), before);  // The old coefficients are kept.
}

}  // namespace
}  // namespace khz::reduced
