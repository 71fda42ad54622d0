// Modal derivatives shared among the processes of a WorkGroup (threads standing in for MPI
// ranks; tests/mpi runs the same under mpirun): every process gets every derivative, equal to
// one process's (anchored: to round-off; free: within MINRES's tolerance), and a failure or a
// cancel on one process stops all.
#include <khz/reduced/basis/modal_derivatives.hpp>
#include <khz/reduced/errors.hpp>
#include <khz/test/derivative_bar.hpp>
#include <khz/test/thread_work_group.hpp>

#include <gtest/gtest.h>

#include <optional>
#include <string>
#include <vector>

namespace khz::reduced {
namespace {

using test::ThreadWorkGroup;

using Bar = test::DerivativeBar;

// Several blocks per rank, not aligned with the ranks' shares.
constexpr int block_size = 5;

ModalDerivatives alone(const Bar& bar) {
  ModalDerivativesOptions options;
  options.block_size = block_size;
  return compute_modal_derivatives(bar.model, bar.modes, options);
}

struct Outcome {
  std::optional<ModalDerivatives> derivatives;
  std::string error;
  std::string cancelled;
};

std::vector<Outcome> run_shared(const Bar& bar, int ranks,
                                const std::function<void(int, ModalDerivativesOptions&)>& adjust) {
  ThreadWorkGroup group(ranks);
  std::vector<Outcome> outcomes(static_cast<std::size_t>(ranks));
  group.run([&](int rank, WorkGroup& member) {
    ModalDerivativesOptions options;
    options.block_size = block_size;
    options.group = &member;
    adjust(rank, options);
    Outcome& outcome = outcomes[static_cast<std::size_t>(rank)];
    try {
      outcome.derivatives = compute_modal_derivatives(bar.model, bar.modes, options);
    } catch (const Cancelled& cancel) {
      outcome.cancelled = cancel.what();
    } catch (const Error& error) {
      outcome.error = error.what();
    }
  });
  return outcomes;
}

TEST(SharedModalDerivatives, AnchoredEqualOneProcessToRoundOffOnEveryRank) {
  const Bar bar(true);
  const ModalDerivatives reference = alone(bar);
  ASSERT_EQ(reference.vectors.cols(), 21);
  for (int ranks : {2, 3}) {
    const std::vector<Outcome> outcomes = run_shared(bar, ranks, [](int, auto&) {});
    for (const Outcome& outcome : outcomes) {
      ASSERT_TRUE(outcome.derivatives) << outcome.error << outcome.cancelled;
      EXPECT_EQ(outcome.derivatives->pairs, reference.pairs);
      EXPECT_LT(test::largest_column_difference(outcome.derivatives->vectors, reference.vectors),
                1e-13)
          << ranks;
    }
  }
}

TEST(SharedModalDerivatives, FreeEqualOneProcessWithinTheSolverTolerance) {
  const Bar bar(false);
  const ModalDerivatives reference = alone(bar);
  ASSERT_EQ(reference.vectors.cols(), 36);
  // Blocks formed from each rank's share: other lockstep groups, each column solved to the
  // relative residual 1e-10 either way.
  const std::vector<Outcome> outcomes = run_shared(bar, 3, [](int, auto&) {});
  for (const Outcome& outcome : outcomes) {
    ASSERT_TRUE(outcome.derivatives) << outcome.error << outcome.cancelled;
    EXPECT_LT(test::largest_column_difference(outcome.derivatives->vectors, reference.vectors),
              1e-6);
    EXPECT_GT(outcome.derivatives->max_minres_iterations, 0);
    EXPECT_EQ(outcome.derivatives->max_minres_iterations,
              outcomes[0].derivatives->max_minres_iterations);  // the group's largest
  }
}

TEST(SharedModalDerivatives, ACancelOnOneRankStopsEveryRank) {
  const Bar bar(true);
  const std::vector<Outcome> outcomes = run_shared(bar, 2, [](int rank, auto& options) {
    options.progress = [rank](const Progress& p) {
      return !(rank == 1 && p.stage == "modal derivatives" && p.done > 0);
    };
  });
  EXPECT_EQ(outcomes[1].cancelled, "cancelled during modal derivatives");
  EXPECT_EQ(outcomes[0].cancelled, "modal derivatives cancelled on rank 1 of 2");
}

TEST(SharedModalDerivatives, BadOptionsOnOneRankFailEveryRankNamingIt) {
  const Bar bar(false);
  const std::vector<Outcome> outcomes = run_shared(bar, 2, [](int rank, auto& options) {
    if (rank == 1) options.max_iterations = 1;  // MINRES cannot converge in one iteration
  });
  EXPECT_NE(outcomes[1].error.find("MINRES did not converge"), std::string::npos)
      << outcomes[1].error;
  EXPECT_NE(outcomes[0].error.find("modal derivatives failed on rank 1 of 2: MINRES"),
            std::string::npos)
      << outcomes[0].error;
}

}  // namespace
}  // namespace khz::reduced
