#include <khz/reduced/errors.hpp>
#include <khz/reduced/meshing/box_mesh.hpp>
#include <khz/reduced/subspace/reconstruction.hpp>
#include <khz/reduced/worker_threads.hpp>
#include <khz/test/allocation_probe.hpp>
#include <khz/test/fixtures.hpp>

#include <gtest/gtest.h>

#include <random>
#include <vector>

namespace khz::reduced {
namespace {

using test::throws_with_message;

// Sums of r = 30 products of entries in [−1, 1]. Measured 0: the matrix-vector product adds the
// columns in the reference loop's order; the bound allows any other order.
constexpr double sum_tolerance = 1e-14;

struct Case {
  VolumeMesh mesh;
  Eigen::MatrixXd basis;
  Eigen::VectorXd q;
};

// A random basis on a box mesh; `cells` large enough makes U big enough to be split over threads.
Case random_case(const Eigen::Vector3i& cells, Eigen::Index r, unsigned seed) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  Case c;
  c.mesh = box_hex_mesh({0.0, 0.0, 0.0}, {2.0, 1.0, 1.0}, cells);
  c.basis =
      Eigen::MatrixXd::NullaryExpr(3 * c.mesh.num_vertices(), r, [&] { return unit(random); });
  c.q = Eigen::VectorXd::NullaryExpr(r, [&] { return unit(random); });
  return c;
}

// u_i = Σ_j U_ij q_j, one row at a time.
Eigen::VectorXd plain_product(const Eigen::MatrixXd& basis, const Eigen::VectorXd& q) {
  Eigen::VectorXd u = Eigen::VectorXd::Zero(basis.rows());
  for (Eigen::Index i = 0; i < basis.rows(); ++i) {
    for (Eigen::Index j = 0; j < basis.cols(); ++j) u[i] += basis(i, j) * q[j];
  }
  return u;
}

class ReconstructionSizes : public ::testing::TestWithParam<Eigen::Vector3i> {};

// A small U (one thread) and one split into many chunks over threads (4410 vertices × 30).
INSTANTIATE_TEST_SUITE_P(Small, ReconstructionSizes, ::testing::Values(Eigen::Vector3i(3, 2, 2)));
INSTANTIATE_TEST_SUITE_P(Large, ReconstructionSizes, ::testing::Values(Eigen::Vector3i(20, 20, 9)));

TEST_P(ReconstructionSizes, DisplacementIsTheProductUq) {
  const Case c = random_case(GetParam(), 30, 3);
  Eigen::VectorXd u = Eigen::VectorXd::Constant(c.basis.rows(), 99.0);  // overwritten
  reconstruct_displacement(c.basis, c.q, u);
  EXPECT_LT((u - plain_product(c.basis, c.q)).cwiseAbs().maxCoeff(), sum_tolerance);

  // Any leading columns form a smaller model (thesis §2.11), viewed without copying.
  Eigen::VectorXd u_leading(c.basis.rows());
  reconstruct_displacement(c.basis.leftCols(7), c.q.head(7), u_leading);
  EXPECT_LT((u_leading - plain_product(c.basis.leftCols(7), c.q.head(7))).cwiseAbs().maxCoeff(),
            sum_tolerance);
}

TEST_P(ReconstructionSizes, PositionsAreRestPlusDisplacement) {
  const Case c = random_case(GetParam(), 30, 5);
  const Eigen::VectorXd u = plain_product(c.basis, c.q);
  VertexMatrix positions(c.mesh.num_vertices(), 3);
  reconstruct_positions(c.mesh.vertices, c.basis, c.q, positions);
  for (Eigen::Index v = 0; v < c.mesh.num_vertices(); ++v) {
    for (int k = 0; k < 3; ++k) {
      EXPECT_NEAR(positions(v, k), c.mesh.vertices(v, k) + u[3 * v + k], sum_tolerance);
    }
  }

  // In place (x += U q), and into a caller's buffer through a Map.
  VertexMatrix in_place = c.mesh.vertices;
  reconstruct_positions(in_place, c.basis, c.q, in_place);
  EXPECT_EQ(in_place, positions);
  std::vector<double> buffer(static_cast<std::size_t>(3 * c.mesh.num_vertices()));
  reconstruct_positions(c.mesh.vertices, c.basis, c.q,
                        Eigen::Map<VertexMatrix>(buffer.data(), c.mesh.num_vertices(), 3));
  EXPECT_EQ(Eigen::Map<VertexMatrix>(buffer.data(), c.mesh.num_vertices(), 3), positions);
}

TEST(Reconstruction, ResultsDoNotDependOnTheThreadCount) {
  const Case c = random_case({20, 20, 9}, 30, 9);
  std::vector<Eigen::VectorXd> displacements;
  std::vector<VertexMatrix> positions;
  for (const int threads : {1, 2, 3}) {
    const ScopedWorkerThreads count(threads);
    displacements.emplace_back(c.basis.rows());
    positions.emplace_back(c.mesh.num_vertices(), 3);
    reconstruct_displacement(c.basis, c.q, displacements.back());
    reconstruct_positions(c.mesh.vertices, c.basis, c.q, positions.back());
  }
  for (std::size_t run = 1; run < displacements.size(); ++run) {
    EXPECT_EQ(displacements[run], displacements[0]) << "run " << run;
    EXPECT_EQ(positions[run], positions[0]) << "run " << run;
  }
}

TEST(Reconstruction, AllocatesNothing) {
  if (!test::allocation_count_sees_malloc) {
    GTEST_LOG_(INFO) << "counting operator new only (sanitized build)";
  }
  for (const Eigen::Vector3i& cells : {Eigen::Vector3i(3, 2, 2), Eigen::Vector3i(20, 20, 9)}) {
    const Case c = random_case(cells, 30, 13);
    Eigen::VectorXd u(c.basis.rows());
    VertexMatrix positions(c.mesh.num_vertices(), 3);
    reconstruct_displacement(c.basis, c.q, u);  // may start the OpenMP thread pool
    test::allocation_count = 0;
    reconstruct_displacement(c.basis, c.q, u);
    reconstruct_positions(c.mesh.vertices, c.basis, c.q, positions);
    EXPECT_EQ(test::allocation_count.load(), 0u) << cells.transpose();
  }
}

TEST(Reconstruction, RejectsWrongSizes) {
  const Case c = random_case({1, 1, 1}, 4, 1);  // 8 vertices, U 24×4
  Eigen::VectorXd u(24);
  VertexMatrix positions(8, 3);
  EXPECT_TRUE(throws_with_message<Error>(
      [&] { reconstruct_displacement(c.basis, Eigen::VectorXd::Zero(5), u); },
      "q has 5 entries, expected 4 (one per basis column)"));
  Eigen::VectorXd short_u(21);
  EXPECT_TRUE(
      throws_with_message<Error>([&] { reconstruct_displacement(c.basis, c.q, short_u); },
                                 "displacement has 21 entries, expected 24 (one per basis row)"));
  EXPECT_TRUE(throws_with_message<Error>(
      [&] { reconstruct_positions(c.mesh.vertices.topRows(7), c.basis, c.q, positions); },
      "basis has 24 rows, expected 21 (three per rest vertex)"));
  EXPECT_TRUE(throws_with_message<Error>(
      [&] { reconstruct_positions(c.mesh.vertices, c.basis, c.q.head(3), positions); },
      "q has 3 entries, expected 4 (one per basis column)"));
  VertexMatrix short_positions(7, 3);
  EXPECT_TRUE(throws_with_message<Error>(
      [&] { reconstruct_positions(c.mesh.vertices, c.basis, c.q, short_positions); },
      "positions has 7 rows, expected 8 (one per rest vertex)"));
}

}  // namespace
}  // namespace khz::reduced
