// ReducedModel::precompute shared among the processes of a WorkGroup (here threads standing in
// for MPI ranks; tests/mpi runs the same under mpirun): the whole model on every process, equal
// to one process's to round-off, and every process stopped together by a failure or a cancel.

#include <khz/reduced/errors.hpp>
#include <khz/reduced/subspace/reduced_model.hpp>
#include <khz/reduced/worker_threads.hpp>
#include <khz/test/thread_work_group.hpp>
#include <khz/test/two_material_box.hpp>

#include <gtest/gtest.h>

#include <array>
#include <atomic>
#include <limits>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include <pthread.h>
#include <sched.h>

namespace khz::reduced {
namespace {

using test::ThreadWorkGroup;
using test::TwoMaterialBox;

// 24×8×8 cells of tetrahedra: tens of element blocks, several rounds for each of 3 ranks.
const TwoMaterialBox& box() {
  static const TwoMaterialBox shared(false, 6, 4e5, Eigen::Vector3i(24, 8, 8));
  return shared;
}

// The blocks one process alone reports as the stage's total.
std::int64_t blocks_alone() {
  std::int64_t total = 0;
  ReducedModelOptions options;
  options.progress = [&](const Progress& p) {
    total = p.total;
    return true;
  };
  (void)ReducedModel::precompute(box().model, box().basis, options);
  return total;
}

double largest_relative_difference(const ReducedModel& a, const ReducedModel& b) {
  double worst = 0.0;
  for (std::size_t g = 0; g < a.groups().size(); ++g) {
    for (std::size_t p = 0; p < a.groups()[g].parts.size(); ++p) {
      const EnergyPolynomial& x = a.groups()[g].parts[p];
      const EnergyPolynomial& y = b.groups()[g].parts[p];
      const auto relative = [](const Eigen::VectorXd& u, const Eigen::VectorXd& v) {
        return (u - v).norm() / v.norm();
      };
      worst = std::max({worst, (x.quadratic - y.quadratic).norm() / y.quadratic.norm(),
                        relative(x.cubic, y.cubic), relative(x.quartic, y.quartic)});
    }
  }
  return worst;
}

// What each rank's call ended with.
struct Outcome {
  std::optional<ReducedModel> model;
  std::string error;      // the message of an Error that is not Cancelled
  std::string cancelled;  // the message of Cancelled
};

std::vector<Outcome> run_shared(int ranks,
                                const std::function<void(int, ReducedModelOptions&)>& adjust,
                                const std::function<Basis(int)>& basis_of) {
  ThreadWorkGroup group(ranks);
  std::vector<Outcome> outcomes(static_cast<std::size_t>(ranks));
  group.run([&](int rank, WorkGroup& member) {
    ReducedModelOptions options;
    options.group = &member;
    adjust(rank, options);
    Outcome& outcome = outcomes[static_cast<std::size_t>(rank)];
    try {
      outcome.model = ReducedModel::precompute(box().model, basis_of(rank), options);
    } catch (const Cancelled& e) {
      outcome.cancelled = e.what();
    } catch (const Error& e) {
      outcome.error = e.what();
    }
  });
  return outcomes;
}

Basis same_basis(int) { return box().basis; }

TEST(SharedPrecompute, EveryRankGetsTheSingleProcessModelToRoundOff) {
  const ReducedModel alone = ReducedModel::precompute(box().model, box().basis);
  for (const int ranks : {1, 2, 3}) {
    SCOPED_TRACE(std::to_string(ranks) + " ranks");
    const auto outcomes = run_shared(
        ranks, [](int, ReducedModelOptions&) {}, same_basis);
    for (const Outcome& outcome : outcomes) {
      ASSERT_TRUE(outcome.model.has_value()) << outcome.error << outcome.cancelled;
      // Each rank summed only its share: a share counted twice or missed would be off by
      // that share's weight, orders of magnitude above round-off.
      EXPECT_LT(largest_relative_difference(*outcome.model, alone), 1e-13);
      EXPECT_LT((outcome.model->mass() - alone.mass()).norm(), 1e-13 * alone.mass().norm());
    }
  }
}

// Ranks with different worker_threads() take rounds of different sizes: they must still meet
// at every checkpoint and sum, or the rank with fewer rounds would sum while the other checks in.
TEST(SharedPrecompute, RanksWithDifferentThreadCountsMeetEquallyOften) {
  cpu_set_t cores;
  ASSERT_EQ(sched_getaffinity(0, sizeof(cores), &cores), 0);
  if (CPU_COUNT(&cores) < 2) GTEST_SKIP() << "needs 2 cores to give the ranks different threads";
  int first_core = 0;
  while (!CPU_ISSET(first_core, &cores)) ++first_core;
  const ReducedModel alone = ReducedModel::precompute(box().model, box().basis);
  std::array<int, 2> threads{};
  const auto outcomes = run_shared(
      2,
      [&](int rank, ReducedModelOptions&) {
        if (rank == 0) {  // this member's thread on one core: worker_threads() = 1
          cpu_set_t one;
          CPU_ZERO(&one);
          CPU_SET(first_core, &one);
          pthread_setaffinity_np(pthread_self(), sizeof(one), &one);
        }
        threads[static_cast<std::size_t>(rank)] = worker_threads();
      },
      same_basis);
  ASSERT_EQ(threads[0], 1);
  ASSERT_GT(threads[1], 1);
  for (const Outcome& outcome : outcomes) {
    ASSERT_TRUE(outcome.model.has_value()) << outcome.error << outcome.cancelled;
    EXPECT_LT(largest_relative_difference(*outcome.model, alone), 1e-13);
  }
}

TEST(SharedPrecompute, ProgressCountsTheWholeGroupOnEveryRank) {
  std::mutex lock;
  std::array<std::vector<std::int64_t>, 2> seen;
  std::int64_t total = 0;
  const auto outcomes = run_shared(
      2,
      [&](int rank, ReducedModelOptions& options) {
        options.progress = [&, rank](const Progress& p) {
          const std::scoped_lock hold(lock);
          seen[static_cast<std::size_t>(rank)].push_back(p.done);
          total = p.total;
          return true;
        };
      },
      same_basis);
  for (const Outcome& outcome : outcomes) ASSERT_TRUE(outcome.model.has_value()) << outcome.error;
  EXPECT_EQ(total, blocks_alone());  // every block of the mesh, not a rank's share
  EXPECT_GE(total, 24);
  for (const auto& reports : seen) {
    ASSERT_GE(reports.size(), 3U);
    EXPECT_EQ(reports.front(), 0);
    EXPECT_EQ(reports.back(), total);
    EXPECT_TRUE(std::is_sorted(reports.begin(), reports.end()));
  }
  EXPECT_EQ(seen[0], seen[1]);  // both ranks see the group's count, checkpoint by checkpoint
}

TEST(SharedPrecompute, ACancelOnOneRankStopsEveryRank) {
  const auto outcomes = run_shared(
      3,
      [](int rank, ReducedModelOptions& options) {
        if (rank == 2) options.progress = [](const Progress&) { return false; };
      },
      same_basis);
  for (const Outcome& outcome : outcomes) {
    EXPECT_FALSE(outcome.model.has_value());
    EXPECT_TRUE(outcome.error.empty()) << outcome.error;
  }
  EXPECT_EQ(outcomes[0].cancelled, "reduced polynomials cancelled on rank 2 of 3");
  EXPECT_EQ(outcomes[2].cancelled, "cancelled during reduced polynomials");
}

TEST(SharedPrecompute, BadInputOnOneRankFailsEveryRankWithItsMessage) {
  const auto outcomes = run_shared(
      2, [](int, ReducedModelOptions&) {},
      [](int rank) {
        Basis basis = box().basis;
        if (rank == 1) basis.vectors(5, 2) = std::numeric_limits<double>::quiet_NaN();
        return basis;
      });
  EXPECT_FALSE(outcomes[0].model.has_value());
  EXPECT_EQ(outcomes[0].error,
            "reduced polynomials failed on rank 1 of 2: ReducedModel: the basis has a non-finite "
            "entry");
  EXPECT_EQ(outcomes[1].error, "ReducedModel: the basis has a non-finite entry");
}

TEST(SharedPrecompute, ACallbackThatThrowsOnOneRankFailsEveryRank) {
  const auto outcomes = run_shared(
      2,
      [](int rank, ReducedModelOptions& options) {
        if (rank == 0) {
          options.progress = [](const Progress& p) -> bool {
            if (p.done > 0) throw IoError("progress file full");
            return true;
          };
        }
      },
      same_basis);
  EXPECT_EQ(outcomes[0].error, "progress file full");
  EXPECT_EQ(outcomes[1].error, "reduced polynomials failed on rank 0 of 2: progress file full");
}

TEST(SharedPrecompute, RanksGivenDifferentBasesAreRefused) {
  const auto outcomes = run_shared(
      2, [](int, ReducedModelOptions&) {},
      [](int rank) {
        Basis basis = box().basis;
        if (rank == 1) basis.vectors.conservativeResize(Eigen::NoChange, 5);
        return basis;
      });
  for (const Outcome& outcome : outcomes) {
    EXPECT_NE(outcome.error.find("were given different models or bases"), std::string::npos)
        << outcome.error;
  }
}

}  // namespace
}  // namespace khz::reduced
