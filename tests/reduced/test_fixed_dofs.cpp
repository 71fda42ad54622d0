#include <khz/reduced/errors.hpp>
#include <khz/reduced/meshing/box_mesh.hpp>
#include <khz/reduced/solvers/fixed_dofs.hpp>
#include <khz/test/fixtures.hpp>

#include <gtest/gtest.h>

#include <Eigen/SparseCore>

#include <cstdlib>
#include <vector>

namespace khz::reduced {
namespace {

using test::throws_with_message;

// 6 vertices, vertices 1 and 4 fixed (4 given twice): free dofs 0–2, 6–11, 15–17.
FixedDofs example() {
  const std::vector<int> fixed{4, 1, 4};
  return FixedDofs(6, fixed);
}

const std::vector<int> free_dofs{0, 1, 2, 6, 7, 8, 9, 10, 11, 15, 16, 17};

// A random symmetric 18×18 matrix with about a third of the entries stored, some of them
// explicit zeros.
SparseMatrix random_full_matrix(unsigned seed) {
  std::srand(seed);
  const Eigen::MatrixXd values = Eigen::MatrixXd::Random(18, 18);
  const Eigen::MatrixXd pattern = Eigen::MatrixXd::Random(18, 18);
  std::vector<Eigen::Triplet<double, int>> entries;
  for (int j = 0; j < 18; ++j) {
    for (int i = 0; i <= j; ++i) {
      if (i != j && pattern(i, j) > -0.3) continue;
      const double v = pattern(i, j) < -0.9 ? 0.0 : values(i, j);
      entries.emplace_back(i, j, v);
      if (i != j) entries.emplace_back(j, i, v);
    }
  }
  SparseMatrix matrix(18, 18);
  matrix.setFromTriplets(entries.begin(), entries.end());
  return matrix;
}

TEST(FixedDofs, CountsAndMapsDofs) {
  const FixedDofs dofs = example();
  EXPECT_EQ(dofs.num_full_dofs(), 18);
  EXPECT_EQ(dofs.num_free_dofs(), 12);
  EXPECT_TRUE(dofs.is_fixed(1));
  EXPECT_TRUE(dofs.is_fixed(4));
  EXPECT_FALSE(dofs.is_fixed(0));
  const Eigen::VectorXd full = Eigen::VectorXd::LinSpaced(18, 0.0, 17.0);
  const Eigen::VectorXd free = dofs.restrict_vector(full);
  ASSERT_EQ(free.size(), 12);
  for (std::size_t k = 0; k < free_dofs.size(); ++k) {
    EXPECT_EQ(free[static_cast<Eigen::Index>(k)], free_dofs[k]);
  }
}

TEST(FixedDofs, VectorsRoundTrip) {
  const FixedDofs dofs = example();
  const Eigen::VectorXd free = Eigen::VectorXd::LinSpaced(12, 1.0, 12.0);
  Eigen::VectorXd full(3);  // resized
  dofs.expand_vector(free, full);
  ASSERT_EQ(full.size(), 18);
  EXPECT_EQ(dofs.restrict_vector(full), free);
  EXPECT_EQ(full.segment<3>(3), Eigen::Vector3d::Zero());
  EXPECT_EQ(full.segment<3>(12), Eigen::Vector3d::Zero());
  // Restricting then expanding zeroes exactly the fixed dofs.
  const Eigen::VectorXd original = Eigen::VectorXd::Constant(18, 2.5);
  dofs.expand_vector(dofs.restrict_vector(original), full);
  EXPECT_EQ(full.sum(), 2.5 * 12);
}

TEST(FixedDofs, MatrixRowsRoundTrip) {
  const FixedDofs dofs = example();
  const Eigen::MatrixXd free = Eigen::MatrixXd::Random(12, 3);
  const Eigen::MatrixXd full = dofs.expand_rows(free);
  ASSERT_EQ(full.rows(), 18);
  ASSERT_EQ(full.cols(), 3);
  EXPECT_EQ(full.middleRows<3>(3), Eigen::MatrixXd::Zero(3, 3));
  EXPECT_EQ(full.middleRows<3>(12), Eigen::MatrixXd::Zero(3, 3));
  for (std::size_t k = 0; k < free_dofs.size(); ++k) {
    EXPECT_EQ(full.row(free_dofs[k]), free.row(static_cast<Eigen::Index>(k)));
  }
  EXPECT_EQ(dofs.restrict_rows(full), free);
  EXPECT_TRUE(throws_with_message<Error>([&] { (void)dofs.restrict_rows(free); },
                                         "full matrix has 12 rows, expected 18"));
  EXPECT_TRUE(throws_with_message<Error>([&] { (void)dofs.expand_rows(full); },
                                         "free matrix has 18 rows, expected 12"));
}

TEST(FixedDofs, NothingFixedIsTheIdentity) {
  const FixedDofs dofs(2, {});
  EXPECT_EQ(dofs.num_free_dofs(), 6);
  const SparseMatrix full = random_full_matrix(1).topLeftCorner(6, 6);
  EXPECT_EQ(Eigen::MatrixXd(dofs.restrict_matrix(full)), Eigen::MatrixXd(full));
}

TEST(FixedDofs, RestrictMatrixIsTheFreeSubmatrix) {
  const FixedDofs dofs = example();
  const SparseMatrix full = random_full_matrix(2);
  const SparseMatrix restricted = dofs.restrict_matrix(full);
  EXPECT_TRUE(restricted.isCompressed());
  const Eigen::MatrixXd dense = Eigen::MatrixXd(full)(free_dofs, free_dofs);
  EXPECT_EQ(Eigen::MatrixXd(restricted), dense);
  // Stored entries survive, explicit zeros included.
  Eigen::Index stored = 0;
  for (const int j : free_dofs) {
    for (SparseMatrix::InnerIterator it(full, j); it; ++it) {
      if (!dofs.is_fixed(it.row() / 3)) ++stored;
    }
  }
  EXPECT_EQ(restricted.nonZeros(), stored);
}

TEST(FixedDofs, RestrictMatrixValuesUpdatesInPlace) {
  const FixedDofs dofs = example();
  SparseMatrix full = random_full_matrix(3);
  SparseMatrix restricted = dofs.restrict_matrix(full);
  const double* storage = restricted.valuePtr();
  full *= -3.0;  // new values, same pattern
  full.coeffRef(6, 6) = 42.0;
  dofs.restrict_matrix_values(full, restricted);
  EXPECT_EQ(restricted.valuePtr(), storage);  // no reallocation
  EXPECT_EQ(Eigen::MatrixXd(restricted), Eigen::MatrixXd(dofs.restrict_matrix(full)));
  EXPECT_EQ(restricted.coeff(3, 3), 42.0);
}

TEST(FixedDofs, RestrictMatrixValuesRejectsAnotherPattern) {
  const FixedDofs dofs = example();
  SparseMatrix restricted = dofs.restrict_matrix(random_full_matrix(4));
  EXPECT_TRUE(throws_with_message<Error>(
      [&] { dofs.restrict_matrix_values(random_full_matrix(5), restricted); },
      "restricted matrix"));
  SparseMatrix wrong_size(5, 5);
  EXPECT_TRUE(throws_with_message<Error>(
      [&] { dofs.restrict_matrix_values(random_full_matrix(4), wrong_size); },
      "restricted matrix is 5×5, expected 12×12"));
}

TEST(FixedDofs, RejectsInvalidInput) {
  const std::vector<int> outside{0, 6};
  EXPECT_TRUE(throws_with_message<Error>([&] { FixedDofs(6, outside); },
                                         "fixed vertex 6 is outside [0, 6)"));
  const std::vector<int> negative{-1};
  EXPECT_TRUE(throws_with_message<Error>([&] { FixedDofs(6, negative); }, "fixed vertex -1"));
  EXPECT_TRUE(throws_with_message<Error>([&] { FixedDofs(-2, {}); }, "negative"));
  const FixedDofs dofs = example();
  EXPECT_TRUE(throws_with_message<Error>([&] { dofs.restrict_vector(Eigen::VectorXd(17)); },
                                         "full vector has 17 entries, expected 18"));
  Eigen::VectorXd full;
  EXPECT_TRUE(throws_with_message<Error>([&] { dofs.expand_vector(Eigen::VectorXd(18), full); },
                                         "free vector has 18 entries, expected 12"));
  EXPECT_TRUE(throws_with_message<Error>([&] { dofs.restrict_matrix(SparseMatrix(18, 17)); },
                                         "full matrix is 18×17, expected 18×18"));
}

TEST(VerticesInBox, SelectsTheClampedEndOfABeam) {
  // A 4×1×1 m beam of 4×1×1 cells: the x = 0 end has the 4 lattice points with i = 0.
  const VolumeMesh beam = box_hex_mesh({0, 0, 0}, {4, 1, 1}, {4, 1, 1});
  const Eigen::AlignedBox3d end(Eigen::Vector3d(-1e-9, -1, -1), Eigen::Vector3d(1e-9, 2, 2));
  const std::vector<int> clamped = vertices_in_box(beam.vertices, end);
  EXPECT_EQ(clamped, (std::vector<int>{0, 5, 10, 15}));
  const FixedDofs dofs(beam.num_vertices(), clamped);
  EXPECT_EQ(dofs.num_free_dofs(), 3 * (20 - 4));
  EXPECT_TRUE(vertices_in_box(beam.vertices, Eigen::AlignedBox3d(Eigen::Vector3d::Constant(5),
                                                                 Eigen::Vector3d::Constant(6)))
                  .empty());
}

}  // namespace
}  // namespace khz::reduced
