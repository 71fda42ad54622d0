#include <khz/reduced/basis/sample_selection.hpp>
#include <khz/reduced/errors.hpp>
#include <khz/test/fixtures.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

namespace khz::reduced {
namespace {

/// Pairwise Euclidean distances of the columns of `points`.
Eigen::MatrixXd distances_of(const Eigen::MatrixXd& points) {
  const Eigen::Index n = points.cols();
  Eigen::MatrixXd d(n, n);
  for (Eigen::Index i = 0; i < n; ++i) {
    for (Eigen::Index j = 0; j < n; ++j) d(i, j) = (points.col(i) - points.col(j)).norm();
  }
  return d;
}

/// Points on a line, as 1 × n columns.
Eigen::MatrixXd on_line(std::initializer_list<double> xs) {
  Eigen::MatrixXd points(1, static_cast<Eigen::Index>(xs.size()));
  Eigen::Index i = 0;
  for (double x : xs) points(0, i++) = x;
  return points;
}

SeparationOptions separated_by(double separation, double kernel_width = 0.0) {
  SeparationOptions options;
  options.separation = separation;
  options.kernel_width = kernel_width;
  return options;
}

void expect_separated(const Eigen::MatrixXd& d, const std::vector<int>& kept, double separation) {
  for (std::size_t a = 0; a < kept.size(); ++a) {
    for (std::size_t b = a + 1; b < kept.size(); ++b) {
      EXPECT_GE(d(kept[a], kept[b]), separation) << kept[a] << ", " << kept[b];
    }
  }
}

TEST(SampleSelection, ClustersCollapseToOneRepresentativeEach) {
  // Three tight clusters (5, 3 and 1 points, spread ≤ 0.1) far apart in 3-D, interleaved.
  std::mt19937 random(3);
  std::uniform_real_distribution<double> jitter(-0.05, 0.05);
  const Eigen::Vector3d centres[] = {{0, 0, 0}, {10, 0, 0}, {0, 10, 5}};
  const int cluster_of[] = {0, 1, 0, 2, 0, 1, 0, 1, 0};
  Eigen::MatrixXd points(3, 9);
  for (Eigen::Index i = 0; i < 9; ++i) {
    // Per entry: GCC 12 with AVX-512 flags a fixed-size Vector3d stored into a dynamic column
    // as an out-of-bounds 512-bit load (-Warray-bounds false positive).
    for (Eigen::Index axis = 0; axis < 3; ++axis) {
      points(axis, i) = centres[cluster_of[i]](axis) + jitter(random);
    }
  }
  const Eigen::MatrixXd d = distances_of(points);
  const SampleSelection selection = select_separated_samples(d, separated_by(1.0));
  ASSERT_EQ(selection.kept.size(), 3u);
  EXPECT_TRUE(std::is_sorted(selection.kept.begin(), selection.kept.end()));
  std::vector<int> clusters;
  for (int k : selection.kept) clusters.push_back(cluster_of[k]);
  std::sort(clusters.begin(), clusters.end());
  EXPECT_EQ(clusters, (std::vector<int>{0, 1, 2}));
  EXPECT_EQ(selection.removed.size(), 6u);
  expect_separated(d, selection.kept, 1.0);
}

TEST(SampleSelection, IdenticalSamplesKeepTheLowestIndex) {
  const Eigen::MatrixXd d = distances_of(on_line({2.0, 2.0, 2.0, 2.0}));
  const SampleSelection selection = select_separated_samples(d, separated_by(0.5));
  EXPECT_EQ(selection.kept, std::vector<int>{0});
  EXPECT_EQ(selection.removed, (std::vector<int>{3, 2, 1}));
  EXPECT_EQ(selection.initial_density, Eigen::VectorXd::Constant(4, 4.0));
}

TEST(SampleSelection, DensestSampleGoesFirst) {
  // A dense triple around 0 (its middle is densest), and a far pair at 100 and 100.5 whose
  // densities tie exactly: the higher index goes, the lower stays.
  const Eigen::MatrixXd d = distances_of(on_line({100.0, 0.0, 0.3, 0.6, 100.5}));
  const SampleSelection selection = select_separated_samples(d, separated_by(1.0));
  ASSERT_GE(selection.removed.size(), 1u);
  EXPECT_EQ(selection.removed.front(), 2);
  Eigen::Index densest = 0;
  selection.initial_density.maxCoeff(&densest);
  EXPECT_EQ(densest, 2);
  // Then 1 and 3 are 0.6 apart with equal density (3 goes), and 4 goes for 0.
  EXPECT_EQ(selection.removed, (std::vector<int>{2, 4, 3}));
  EXPECT_EQ(selection.kept, (std::vector<int>{0, 1}));
}

TEST(SampleSelection, DensityIsUpdatedAsNeighboursGo) {
  // Five identical samples at 0, then 0.8 and 1.6; δ = h = 1. The cluster goes first, down to
  // one member, whose density has then dropped below that of the sample at 0.8: that one goes
  // next and the survivors at 0 and 1.6 are separated. A density fixed at the start would keep
  // removing the cluster's last member (and then 0.8), leaving a single sample.
  const Eigen::MatrixXd d = distances_of(on_line({0.0, 0.0, 0.0, 0.0, 0.0, 0.8, 1.6}));
  const SampleSelection selection = select_separated_samples(d, separated_by(1.0));
  EXPECT_EQ(selection.removed, (std::vector<int>{4, 3, 2, 1, 5}));
  EXPECT_EQ(selection.kept, (std::vector<int>{0, 6}));
}

TEST(SampleSelection, RandomSamplesEndSeparatedAndDeterministic) {
  for (unsigned seed = 1; seed <= 3; ++seed) {
    SCOPED_TRACE(seed);
    std::mt19937 random(seed);
    std::normal_distribution<double> normal;
    Eigen::MatrixXd points(4, 150);
    for (Eigen::Index i = 0; i < points.size(); ++i) points.data()[i] = normal(random);
    const Eigen::MatrixXd d = distances_of(points);
    const SampleSelection first = select_separated_samples(d, separated_by(1.2, 2.0));
    const SampleSelection second = select_separated_samples(d, separated_by(1.2, 2.0));
    EXPECT_EQ(first.kept, second.kept);
    EXPECT_EQ(first.removed, second.removed);
    EXPECT_EQ(first.kept.size() + first.removed.size(), 150u);
    EXPECT_GT(first.kept.size(), 10u);
    EXPECT_LT(first.kept.size(), 150u);
    expect_separated(d, first.kept, 1.2);
    // Only the upper triangle is read: garbage below the diagonal changes nothing.
    Eigen::MatrixXd upper = d.triangularView<Eigen::StrictlyUpper>();
    upper.diagonal().setConstant(-7.0);
    EXPECT_EQ(select_separated_samples(upper, separated_by(1.2, 2.0)).kept, first.kept);
  }
}

TEST(SampleSelection, ZeroSeparationKeepsEverything) {
  const Eigen::MatrixXd d = distances_of(on_line({0.0, 0.0, 1.0}));
  const SampleSelection selection = select_separated_samples(d, SeparationOptions{});
  EXPECT_EQ(selection.kept, (std::vector<int>{0, 1, 2}));
  EXPECT_TRUE(selection.removed.empty());
  // h = δ = 0: the kernel's limit counts the samples at distance 0.
  EXPECT_EQ(selection.initial_density, Eigen::Vector3d(2.0, 2.0, 1.0));
  EXPECT_TRUE(select_separated_samples(Eigen::MatrixXd(0, 0), separated_by(1.0)).kept.empty());
}

TEST(SampleSelection, RejectsBadInput) {
  EXPECT_TRUE(test::throws_with_message<Error>(
      [] { select_separated_samples(Eigen::MatrixXd::Zero(2, 3), separated_by(1.0)); },
      "select_separated_samples: the distance matrix is 2 × 3, not square"));
  Eigen::MatrixXd d = distances_of(on_line({0.0, 1.0, 2.0}));
  d(0, 2) = -1.0;
  EXPECT_TRUE(test::throws_with_message<Error>(
      [&] { select_separated_samples(d, separated_by(1.0)); },
      "select_separated_samples: distance (0, 2) is -1; distances must be finite and "
      "non-negative"));
  d(0, 2) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(select_separated_samples(d, separated_by(1.0)), Error);
  EXPECT_TRUE(test::throws_with_message<Error>(
      [] { select_separated_samples(Eigen::MatrixXd::Zero(1, 1), separated_by(-0.5)); },
      "SeparationOptions: separation must be finite and non-negative, got -0.5"));
  EXPECT_TRUE(test::throws_with_message<Error>(
      [] {
        select_separated_samples(Eigen::MatrixXd::Zero(1, 1),
                                 separated_by(1.0, std::numeric_limits<double>::infinity()));
      },
      "SeparationOptions: kernel_width must be finite and non-negative, got inf"));
}

/// A small symmetric positive definite sparse "mass matrix": tridiagonal, diagonally dominant.
SparseMatrix small_mass(Eigen::Index size) {
  SparseMatrix mass(size, size);
  std::vector<Eigen::Triplet<double>> entries;
  for (Eigen::Index i = 0; i < size; ++i) {
    entries.emplace_back(i, i, 2.0 + 0.1 * static_cast<double>(i));
    if (i + 1 < size) {
      entries.emplace_back(i, i + 1, 0.5);
      entries.emplace_back(i + 1, i, 0.5);
    }
  }
  mass.setFromTriplets(entries.begin(), entries.end());
  return mass;
}

TEST(SampleSelection, MassDistancesMatchTheDefinition) {
  const SparseMatrix mass = small_mass(12);
  std::mt19937 random(5);
  std::normal_distribution<double> normal;
  Eigen::MatrixXd samples(12, 40);  // two progress blocks
  for (Eigen::Index i = 0; i < samples.size(); ++i) samples.data()[i] = normal(random);
  samples.col(7) = samples.col(3);
  int reports = 0;
  const Eigen::MatrixXd d = mass_distances(samples, mass, [&](const Progress& progress) {
    EXPECT_EQ(progress.stage, "mass distances");
    EXPECT_EQ(progress.total, 2);
    EXPECT_EQ(progress.done, reports);
    ++reports;
    return true;
  });
  EXPECT_EQ(reports, 3);
  const Eigen::MatrixXd dense_mass(mass);
  ASSERT_EQ(d.rows(), 40);
  EXPECT_EQ(d, d.transpose());
  for (Eigen::Index i = 0; i < 40; ++i) {
    for (Eigen::Index j = 0; j < 40; ++j) {
      if ((i == 3 && j == 7) || (i == 7 && j == 3)) continue;
      const Eigen::VectorXd diff = samples.col(i) - samples.col(j);
      const double expected = std::sqrt(diff.dot(dense_mass * diff));
      EXPECT_NEAR(d(i, j), expected, 1e-12 * (1.0 + expected)) << i << ", " << j;
    }
  }
  // Identical columns: cancellation in Gᵢᵢ + Gⱼⱼ − 2Gᵢⱼ leaves at most ~√ε·‖x‖_M (‖x‖_M ≈ 5).
  EXPECT_LT(d(3, 7), 1e-6);
}

TEST(SampleSelection, MassDistancesCanBeCancelledAndCheckSizes) {
  const SparseMatrix mass = small_mass(6);
  const Eigen::MatrixXd samples = Eigen::MatrixXd::Ones(6, 3);
  EXPECT_TRUE(test::throws_with_message<Cancelled>(
      [&] { mass_distances(samples, mass, [](const Progress&) { return false; }); },
      "cancelled during mass distances"));
  EXPECT_TRUE(test::throws_with_message<Error>(
      [&] { mass_distances(Eigen::MatrixXd::Ones(5, 3), mass); },
      "mass_distances: the samples have 5 rows but the mass matrix is 6 × 6"));
  Eigen::MatrixXd bad = samples;
  bad(2, 1) = std::numeric_limits<double>::infinity();
  EXPECT_TRUE(test::throws_with_message<Error>([&] { mass_distances(bad, mass); },
                                               "mass_distances: sample 1 is not finite"));
}

TEST(SampleSelection, DistancesFromGramClampCancellation) {
  Eigen::Matrix3d gram;
  gram << 4, 2, 4, 2, 1, 2, 4, 2, 4 + 1e-15;
  const Eigen::MatrixXd d = distances_from_gram(gram);
  EXPECT_EQ(d(0, 1), 1.0);  // ‖x‖ = 2, ‖y‖ = 1, parallel
  EXPECT_GE(d(0, 2), 0.0);
  EXPECT_LT(d(0, 2), 1e-7);
  EXPECT_EQ(d.diagonal(), Eigen::Vector3d::Zero());
  EXPECT_THROW(distances_from_gram(Eigen::MatrixXd::Zero(2, 1)), Error);
}

}  // namespace
}  // namespace khz::reduced
