#include <khz/reduced/errors.hpp>
#include <khz/reduced/solvers/sparse_cholesky.hpp>
#include <khz/test/fixtures.hpp>

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <Eigen/SparseCore>

#include <array>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <random>
#include <vector>

namespace khz::reduced {
namespace {

using test::throws_with_message;
using Kind = SparseCholesky::Kind;

// Relative error of the solution against Eigen's dense factorizations, ≈ 10× the measured
// worst case: ≤ 8e-16 for the positive definite matrices below (condition numbers ≲ 1e2), 1.6e-14
// for the indefinite one, whose LDLᵀ factorization has no pivoting to keep it stable.
constexpr double solution_tolerance = 1e-14;
constexpr double indefinite_tolerance = 2e-13;

// A random symmetric matrix with the sparsity of a 3D grid graph (as FEM matrices have): n
// unknowns, each coupled to up to 6 neighbours, off-diagonals in [−1, 1], diagonal
// `diagonal_shift` + the absolute row sum (so shift > 0 gives a positive definite matrix).
SparseMatrix grid_matrix(int side, double diagonal_shift, std::uint32_t seed) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> value(-1.0, 1.0);
  const int n = side * side * side;
  std::vector<Eigen::Triplet<double, int>> entries;
  Eigen::VectorXd diagonal = Eigen::VectorXd::Constant(n, diagonal_shift);
  const auto index = [side](int i, int j, int k) { return i + side * (j + side * k); };
  for (int k = 0; k < side; ++k) {
    for (int j = 0; j < side; ++j) {
      for (int i = 0; i < side; ++i) {
        const int a = index(i, j, k);
        const std::array<std::array<int, 3>, 3> steps{{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
        for (const auto& s : steps) {
          if (i + s[0] >= side || j + s[1] >= side || k + s[2] >= side) continue;
          const int b = index(i + s[0], j + s[1], k + s[2]);
          const double v = value(random);
          entries.emplace_back(a, b, v);
          entries.emplace_back(b, a, v);
          diagonal[a] += std::abs(v);
          diagonal[b] += std::abs(v);
        }
      }
    }
  }
  for (int a = 0; a < n; ++a) entries.emplace_back(a, a, diagonal[a]);
  SparseMatrix matrix(n, n);
  matrix.setFromTriplets(entries.begin(), entries.end());
  return matrix;
}

double relative_error(const Eigen::MatrixXd& x, const Eigen::MatrixXd& expected) {
  return (x - expected).norm() / expected.norm();
}

TEST(SparseCholesky, LltMatchesDenseSolution) {
  const SparseMatrix a = grid_matrix(6, 0.5, 1);  // 216 unknowns
  SparseCholesky solver;
  solver.analyze(a);
  EXPECT_EQ(solver.rows(), 216);
  EXPECT_FALSE(solver.factorized());
  solver.factorize(a);
  EXPECT_TRUE(solver.factorized());
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(216, -1.0, 2.0);
  const Eigen::VectorXd expected = Eigen::MatrixXd(a).llt().solve(b);
  EXPECT_LT(relative_error(solver.solve(b), expected), solution_tolerance);
}

TEST(SparseCholesky, SupernodalLltOnALargerMatrix) {
  // 20³ unknowns: enough fill that CHOLMOD chooses its supernodal method.
  const SparseMatrix a = grid_matrix(20, 0.1, 2);
  SparseCholesky solver;
  solver.factorize(a);  // analyzes implicitly
  const Eigen::VectorXd expected = Eigen::VectorXd::LinSpaced(a.rows(), -3.0, 1.0);
  const Eigen::VectorXd x = solver.solve(Eigen::VectorXd(a * expected));
  EXPECT_LT(relative_error(x, expected), solution_tolerance);
}

TEST(SparseCholesky, SolvesManyRightHandSidesAtOnce) {
  const SparseMatrix a = grid_matrix(5, 1.0, 3);
  SparseCholesky solver;
  solver.factorize(a);
  std::srand(3);
  const Eigen::MatrixXd b = Eigen::MatrixXd::Random(a.rows(), 7);
  const Eigen::MatrixXd x = solver.solve(b);
  ASSERT_EQ(x.cols(), 7);
  EXPECT_LT(relative_error(x, Eigen::MatrixXd(a).llt().solve(b)), solution_tolerance);
  for (Eigen::Index j = 0; j < b.cols(); ++j) {
    const Eigen::VectorXd column = b.col(j);
    EXPECT_LT((solver.solve(column) - x.col(j)).norm(), 1e-14 * x.col(j).norm());
  }
  EXPECT_EQ(solver.solve(Eigen::MatrixXd(a.rows(), 0)).cols(), 0);
}

// solve_lower / solve_upper split A⁻¹ = (PᵀL⁻ᵀ)(L⁻¹P): checked through their defining
// identities, for the simplicial (small) and supernodal (20³) factorizations.
TEST(SparseCholesky, FactorHalvesComposeToTheInverseAndGiveTheANorm) {
  for (const int side : {5, 20}) {
    const SparseMatrix a = grid_matrix(side, 0.3, 7);
    SparseCholesky solver;
    solver.factorize(a);
    std::srand(5);
    const Eigen::MatrixXd b = Eigen::MatrixXd::Random(a.rows(), 3);
    const Eigen::MatrixXd x = solver.solve_upper(solver.solve_lower(b));
    EXPECT_LT(relative_error(x, solver.solve(b)), 1e-13) << side;
    // z = L⁻¹P(A b) = LᵀP b, so zᵀz = bᵀAb: the A-inner product becomes the Euclidean one.
    const Eigen::MatrixXd z = solver.solve_lower(Eigen::MatrixXd(a * b));
    const Eigen::MatrixXd gram = b.transpose() * (a * b);
    EXPECT_LT((z.transpose() * z - gram).norm(), 1e-12 * gram.norm()) << side;
    // Lᵀ is upper triangular in the permuted order: solve_upper undoes the change of coordinates.
    EXPECT_LT(relative_error(solver.solve_upper(z), b), 1e-12) << side;
  }
  SparseCholesky ldlt(SparseCholesky::Kind::ldlt);
  ldlt.factorize(grid_matrix(3, 1.0, 1));
  EXPECT_TRUE(test::throws_with_message<Error>(
      [&] { (void)ldlt.solve_lower(Eigen::MatrixXd::Ones(27, 1)); },
      "solve_lower needs an llt factorization"));
}

TEST(SparseCholesky, ReusesTheAnalysisForNewValues) {
  SparseMatrix a = grid_matrix(6, 0.5, 4);
  SparseCholesky solver;
  solver.analyze(a);
  const Eigen::VectorXd b = Eigen::VectorXd::Ones(a.rows());
  for (int round = 0; round < 3; ++round) {
    // Same pattern, new values: the Newton-loop use.
    a = grid_matrix(6, 0.5 + round, 10 + static_cast<std::uint32_t>(round));
    solver.factorize(a);
    EXPECT_LT(relative_error(solver.solve(b), Eigen::MatrixXd(a).llt().solve(b)),
              solution_tolerance);
  }
}

TEST(SparseCholesky, KeepsExplicitZerosAndAcceptsUncompressedMatrices) {
  SparseMatrix a = grid_matrix(4, 1.0, 5);
  // Zero out an off-diagonal pair without removing it from the pattern.
  a.coeffRef(0, 1) = 0.0;
  a.coeffRef(1, 0) = 0.0;
  SparseCholesky solver;
  solver.analyze(a);
  SparseMatrix uncompressed = a;
  uncompressed.reserve(Eigen::VectorXi::Constant(a.cols(), 2));  // leaves gaps between columns
  ASSERT_FALSE(uncompressed.isCompressed());
  solver.factorize(uncompressed);
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(a.rows(), 1.0, 2.0);
  EXPECT_LT(relative_error(solver.solve(b), Eigen::MatrixXd(a).llt().solve(b)), solution_tolerance);
}

// A positive definite grid matrix shifted by −σI, σ halfway between two eigenvalues: symmetric,
// indefinite, safely nonsingular.
SparseMatrix indefinite_matrix() {
  SparseMatrix a = grid_matrix(5, 0.5, 6);
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(Eigen::MatrixXd(a), Eigen::EigenvaluesOnly);
  const double sigma = 0.5 * (eigen.eigenvalues()[40] + eigen.eigenvalues()[41]);
  SparseMatrix identity(a.rows(), a.cols());
  identity.setIdentity();
  return a - sigma * identity;
}

TEST(SparseCholesky, LltRejectsIndefiniteMatrix) {
  SparseCholesky solver;
  EXPECT_TRUE(throws_with_message<SolverError>([&] { solver.factorize(indefinite_matrix()); },
                                               "matrix is not positive definite (column "));
  EXPECT_FALSE(solver.factorized());
  EXPECT_TRUE(throws_with_message<Error>([&] { solver.solve(Eigen::VectorXd::Ones(125)); },
                                         "no factorization"));
  EXPECT_FALSE(solver.try_factorize(indefinite_matrix()));
  // The analysis survives the failure: a definite matrix with the same pattern factorizes.
  EXPECT_TRUE(solver.try_factorize(grid_matrix(5, 0.5, 6)));
  EXPECT_TRUE(solver.factorized());
}

TEST(SparseCholesky, SupernodalLltRejectsIndefiniteMatrixThatLdltSolves) {
  const SparseMatrix definite = grid_matrix(20, 0.1, 12);
  SparseMatrix a = definite;
  a.coeffRef(4321, 4321) = -1.0;  // e_kᵀ A e_k < 0: indefinite
  SparseCholesky llt;
  EXPECT_TRUE(throws_with_message<SolverError>([&] { llt.factorize(a); },
                                               "matrix is not positive definite (column "));
  EXPECT_TRUE(llt.try_factorize(definite));  // the failed factor is reusable
  SparseCholesky ldlt(Kind::ldlt);
  ldlt.factorize(a);
  const Eigen::VectorXd expected = Eigen::VectorXd::LinSpaced(a.rows(), -3.0, 1.0);
  EXPECT_LT(relative_error(ldlt.solve(a * expected), expected), indefinite_tolerance);
}

TEST(SparseCholesky, NamesTheColumnWhereLltBreaksDown) {
  SparseMatrix a(4, 4);
  a.insert(0, 0) = 1.0;
  a.insert(1, 1) = 2.0;
  a.insert(2, 2) = -3.0;
  a.insert(3, 3) = 4.0;
  SparseCholesky solver;
  EXPECT_TRUE(throws_with_message<SolverError>([&] { solver.factorize(a); },
                                               "matrix is not positive definite (column 2)"));
}

TEST(SparseCholesky, LdltSolvesIndefiniteMatrix) {
  const SparseMatrix a = indefinite_matrix();
  SparseCholesky solver(Kind::ldlt);
  EXPECT_EQ(solver.kind(), Kind::ldlt);
  solver.factorize(a);
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(a.rows(), -1.0, 1.0);
  EXPECT_LT(relative_error(solver.solve(b), Eigen::MatrixXd(a).partialPivLu().solve(b)),
            indefinite_tolerance);
}

TEST(SparseCholesky, LdltRejectsZeroPivot) {
  // Nonsingular, but LDLᵀ without pivoting has no first pivot (a documented limitation).
  SparseMatrix a(2, 2);
  a.insert(0, 1) = 1.0;
  a.insert(1, 0) = 1.0;
  a.insert(0, 0) = 0.0;
  a.insert(1, 1) = 0.0;
  SparseCholesky solver(Kind::ldlt);
  EXPECT_TRUE(throws_with_message<SolverError>([&] { solver.factorize(a); },
                                               "matrix is singular (zero pivot in column "));
}

// The Laplacian of the grid graph: positive semidefinite, constant vectors in its kernel.
SparseMatrix singular_matrix(int side = 4) {
  SparseMatrix a = grid_matrix(side, 0.0, 7);
  for (Eigen::Index j = 0; j < a.outerSize(); ++j) {
    for (SparseMatrix::InnerIterator it(a, j); it; ++it) {
      if (it.row() != it.col()) it.valueRef() = -std::abs(it.value());
    }
  }
  return a;
}

TEST(SparseCholesky, RejectsSingularMatrix) {
  SparseCholesky llt;
  EXPECT_TRUE(
      throws_with_message<SolverError>([&] { llt.factorize(singular_matrix()); }, "matrix is"));
  EXPECT_FALSE(llt.factorized());
  SparseCholesky ldlt(Kind::ldlt);
  EXPECT_TRUE(
      throws_with_message<SolverError>([&] { ldlt.factorize(singular_matrix()); }, "singular"));
  EXPECT_FALSE(ldlt.factorized());
  // Larger: rounding leaves the last pivot at ≈ 1e-14 of the largest instead of 0.
  SparseCholesky larger(Kind::ldlt);
  EXPECT_TRUE(throws_with_message<SolverError>([&] { larger.factorize(singular_matrix(10)); },
                                               "matrix is numerically singular"));
}

TEST(SparseCholesky, RejectsMisuse) {
  SparseCholesky solver;
  EXPECT_TRUE(throws_with_message<Error>([&] { solver.analyze(SparseMatrix(3, 4)); },
                                         "3×4 matrix: it is not square"));
  EXPECT_TRUE(throws_with_message<Error>([&] { solver.solve(Eigen::VectorXd::Ones(3)); },
                                         "no factorization"));
  const SparseMatrix a = grid_matrix(3, 1.0, 8);
  solver.factorize(a);
  EXPECT_TRUE(throws_with_message<Error>([&] { solver.solve(Eigen::VectorXd::Ones(26)); },
                                         "right-hand side has 26 rows, the matrix 27"));
  EXPECT_TRUE(throws_with_message<Error>([&] { solver.factorize(grid_matrix(4, 1.0, 8)); },
                                         "does not have the analyzed pattern"));
  SparseMatrix more = a;
  more.coeffRef(0, 26) = 0.5;
  more.coeffRef(26, 0) = 0.5;
  EXPECT_TRUE(throws_with_message<Error>([&] { solver.factorize(more); },
                                         "does not have the analyzed pattern"));
  solver.analyze(more);  // a new analysis accepts it
  EXPECT_NO_THROW(solver.factorize(more));
}

TEST(SparseCholesky, IsMoveable) {
  const SparseMatrix a = grid_matrix(3, 1.0, 9);
  SparseCholesky first;
  first.factorize(a);
  SparseCholesky second(std::move(first));
  const Eigen::VectorXd b = Eigen::VectorXd::Ones(a.rows());
  EXPECT_LT(relative_error(second.solve(b), Eigen::MatrixXd(a).llt().solve(b)), solution_tolerance);
  SparseCholesky third(Kind::ldlt);
  third = std::move(second);
  EXPECT_EQ(third.kind(), Kind::llt);
  EXPECT_TRUE(third.factorized());
}

}  // namespace
}  // namespace khz::reduced
