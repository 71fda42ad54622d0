// khz::mpi::MpiWorkGroup under mpiexec: its collectives, and ReducedModel's precompute shared
// over the ranks against the same precompute on one rank alone.

#include <khz/mpi/mpi_work_group.hpp>
#include <khz/reduced/errors.hpp>
#include <khz/reduced/subspace/reduced_model.hpp>
#include <khz/reduced/worker_threads.hpp>
#include <khz/test/two_material_box.hpp>

#include <gtest/gtest.h>

#include <limits>
#include <string>
#include <vector>

namespace khz::mpi {
namespace {

using reduced::Basis;
using reduced::GroupStatus;
using reduced::ReducedModel;
using reduced::ReducedModelOptions;

int world_size() {
  int size = 0;
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  return size;
}

TEST(MpiWorkGroup, SumsOverEveryRank) {
  MpiWorkGroup group;
  ASSERT_EQ(group.size(), world_size());
  ASSERT_GE(group.size(), 2) << "run under mpiexec -n 2 or more";
  std::vector<double> values{group.rank() + 1.0, 0.5};
  group.sum(values);
  const double n = group.size();
  EXPECT_EQ(values[0], n * (n + 1) / 2);
  EXPECT_EQ(values[1], 0.5 * n);
}

TEST(MpiWorkGroup, ACheckpointNamesTheLowestRankInTheWorstState) {
  MpiWorkGroup group;
  GroupStatus mine;
  mine.done = 10 * (group.rank() + 1);
  const GroupStatus calm = group.checkpoint(mine);
  EXPECT_EQ(calm.state, GroupStatus::State::running);
  EXPECT_EQ(calm.done, 10 * group.size() * (group.size() + 1) / 2);
  EXPECT_EQ(calm.rank, -1);

  // Rank 0 cancels, every other rank fails: the failure of rank 1 wins.
  mine.state = group.rank() == 0 ? GroupStatus::State::cancelled : GroupStatus::State::failed;
  mine.message = "from rank " + std::to_string(group.rank());
  const GroupStatus stopped = group.checkpoint(mine);
  EXPECT_EQ(stopped.state, GroupStatus::State::failed);
  EXPECT_EQ(stopped.rank, 1);
  EXPECT_EQ(stopped.message, "from rank 1");
}

const test::TwoMaterialBox& box() {
  static const test::TwoMaterialBox shared(false, 8, 4e5, Eigen::Vector3i(24, 8, 8));
  return shared;
}

TEST(MpiPrecompute, EveryRankGetsTheSingleProcessModelToRoundOff) {
  const ReducedModel alone = ReducedModel::precompute(box().model, box().basis);
  MpiWorkGroup group;
  ReducedModelOptions options;
  options.group = &group;
  const ReducedModel shared = ReducedModel::precompute(box().model, box().basis, options);
  for (std::size_t g = 0; g < alone.groups().size(); ++g) {
    for (std::size_t p = 0; p < alone.groups()[g].parts.size(); ++p) {
      const auto& a = alone.groups()[g].parts[p];
      const auto& b = shared.groups()[g].parts[p];
      // Each rank summed only its share: a share missed or counted twice would be off by its
      // whole weight, not by round-off.
      EXPECT_LT((a.quadratic - b.quadratic).norm(), 1e-13 * a.quadratic.norm());
      EXPECT_LT((a.cubic - b.cubic).norm(), 1e-13 * a.cubic.norm());
      EXPECT_LT((a.quartic - b.quartic).norm(), 1e-13 * a.quartic.norm());
    }
  }
}

TEST(MpiPrecompute, RanksWithDifferentThreadCountsAgree) {
  const ReducedModel alone = ReducedModel::precompute(box().model, box().basis);
  MpiWorkGroup group;
  // Rank r runs r + 1 threads and so takes larger rounds of blocks than the ranks before it, yet
  // all must meet at the same checkpoints.
  const reduced::ScopedWorkerThreads threads(group.rank() + 1);
  ReducedModelOptions options;
  options.group = &group;
  const ReducedModel shared = ReducedModel::precompute(box().model, box().basis, options);
  const auto& a = alone.groups()[1].parts[0].quartic;
  const auto& b = shared.groups()[1].parts[0].quartic;
  EXPECT_LT((a - b).norm(), 1e-13 * a.norm());
}

TEST(MpiPrecompute, BadInputOnOneRankEndsEveryRankWithItsMessage) {
  MpiWorkGroup group;
  ReducedModelOptions options;
  options.group = &group;
  Basis basis = box().basis;
  if (group.rank() == 1) basis.vectors(4, 1) = std::numeric_limits<double>::infinity();
  try {
    (void)ReducedModel::precompute(box().model, basis, options);
    ADD_FAILURE() << "no rank may return a model";
  } catch (const reduced::Error& e) {
    const std::string expected = group.rank() == 1
                                     ? "ReducedModel: the basis has a non-finite entry"
                                     : "reduced polynomials failed on rank 1 of " +
                                           std::to_string(group.size()) +
                                           ": ReducedModel: the basis has a non-finite entry";
    EXPECT_EQ(e.what(), expected);
  }
}

TEST(MpiPrecompute, ACancelOnTheLastRankStopsEveryRank) {
  MpiWorkGroup group;
  ReducedModelOptions options;
  options.group = &group;
  const int last = group.size() - 1;
  if (group.rank() == last) options.progress = [](const reduced::Progress&) { return false; };
  EXPECT_THROW((void)ReducedModel::precompute(box().model, box().basis, options),
               reduced::Cancelled);
}

}  // namespace
}  // namespace khz::mpi
