// worker_threads(): one setting bounds the threads a precomputation runs, its dependencies'
// included (issue 23 item 4). Counted from outside (test::other_threads_that_ran): the process's
// threads that ran while
// - a nonlinear static solve ran: K assembled with OpenMP, factorized by CHOLMOD's supernodal
//   method (OpenMP, asking for 4 threads whatever OMP_NUM_THREADS says) through OpenBLAS;
// - a modal-derivative basis was built: ARPACK (OpenBLAS), CHOLMOD solves, mass-PCA (Eigen).
// Each setting is measured on the second run under it: a change of setting wakes a pool thread
// or two once, to resize its team, without work. Without the bound, the solve runs 4 threads
// besides the caller on this 2-core machine (3 of CHOLMOD's, 1 of OpenBLAS's).

#include <khz/reduced/basis/modal_derivative_basis.hpp>
#include <khz/reduced/errors.hpp>
#include <khz/reduced/solvers/static_solver.hpp>
#include <khz/reduced/worker_threads.hpp>
#include <khz/test/cantilever.hpp>
#include <khz/test/fixtures.hpp>
#include <khz/test/threads_that_ran.hpp>

#include <gtest/gtest.h>

#include <sched.h>

#include <cstdlib>
#include <string>
#include <utility>
#include <vector>

namespace khz::reduced {
namespace {

const test::Cantilever& beam() {
  static const test::Cantilever instance(1.0, 0.1, 4, Material::stvk(1e7, 0.3, 1000.0));
  return instance;
}

/// A nonlinear static solve of a 3k-dof hexahedral cantilever under a tip load.
void nonlinear_static_solve() {
  StaticSolveOptions options;
  options.load_steps = 2;
  const StaticSolution solution = solve_static(
      beam().model, beam().clamped, beam().tip_load(Eigen::Vector3d(0, 0, -20.0)), options);
  ASSERT_TRUE(solution.displacement.allFinite());
}

/// A modal-derivative basis (k = 6, r = 15) of the same cantilever.
void modal_derivative_basis_build() {
  ModalDerivativeBasisOptions options;
  options.modes.num_modes = 6;
  options.basis_size = 15;
  const Basis basis = modal_derivative_basis(beam().model, beam().clamped, options);
  ASSERT_EQ(basis.size(), 15);
}

TEST(WorkerThreads, OneThreadMeansNoOtherThreadRuns) {
  const ScopedWorkerThreads one(1);
  EXPECT_EQ(worker_threads(), 1);
  using Work = std::pair<const char*, void (*)()>;
  for (const auto& [name, work] :
       {Work{"solve", nonlinear_static_solve}, Work{"basis", modal_derivative_basis_build}}) {
    const std::vector<std::string> ran = test::other_threads_in_a_second_run(work);
    EXPECT_TRUE(ran.empty()) << name << test::listed(ran);
  }
}

// With n threads at most n − 1 pool threads of OpenMP and n − 1 of OpenBLAS take part: each
// library keeps its own pool, and at any moment at most n threads of the two work.
TEST(WorkerThreads, NThreadsBoundEachPool) {
  if (test::usable_cores() < 2) GTEST_SKIP() << "one core: nothing to share";
  const ScopedWorkerThreads two(2);
  const std::vector<std::string> ran = test::other_threads_in_a_second_run(nonlinear_static_solve);
  EXPECT_GE(ran.size(), 1U) << "the solve ran in parallel";
  EXPECT_LE(ran.size(), 2U) << test::listed(ran);
}

TEST(WorkerThreads, TheDefaultIsTheCoresTheCallerMayUse) {
  ASSERT_EQ(std::getenv("OMP_NUM_THREADS"), nullptr) << "run without OMP_NUM_THREADS";
  set_worker_threads(0);
  const int cores = test::usable_cores();
  EXPECT_EQ(worker_threads(), cores);
  const std::vector<std::string> ran = test::other_threads_in_a_second_run(nonlinear_static_solve);
  EXPECT_LE(ran.size(), 2U * static_cast<std::size_t>(cores - 1)) << test::listed(ran);

  // A thread kept off a core (as a pinned haptic loop keeps the others) counts one fewer.
  if (cores >= 2) {
    cpu_set_t all, fewer;
    ASSERT_EQ(sched_getaffinity(0, sizeof(all), &all), 0);
    fewer = all;
    for (int cpu = CPU_SETSIZE - 1; cpu >= 0; --cpu) {
      if (CPU_ISSET(cpu, &fewer)) {
        CPU_CLR(cpu, &fewer);
        break;
      }
    }
    ASSERT_EQ(sched_setaffinity(0, sizeof(fewer), &fewer), 0);
    EXPECT_EQ(worker_threads(), cores - 1);
    ASSERT_EQ(sched_setaffinity(0, sizeof(all), &all), 0);
  }
}

TEST(WorkerThreads, SettingsAndTheirErrors) {
  set_worker_threads(3);
  EXPECT_EQ(worker_threads(), 3);
  {
    const ScopedWorkerThreads one(1);
    EXPECT_EQ(worker_threads(), 1);
  }
  EXPECT_EQ(worker_threads(), 3);
  EXPECT_TRUE(test::throws_with_message<Error>([] { set_worker_threads(-1); }, "got -1"));
  EXPECT_EQ(worker_threads(), 3);

  ASSERT_EQ(setenv("KHZ_TEST_THREADS", "2", 1), 0);
  EXPECT_EQ(set_worker_threads_from_environment("KHZ_TEST_THREADS"), 2);
  EXPECT_EQ(worker_threads(), 2);
  for (const char* bad : {"0", "two", "2x", "-3", " 2"}) {
    ASSERT_EQ(setenv("KHZ_TEST_THREADS", bad, 1), 0);
    EXPECT_TRUE(test::throws_with_message<Error>(
        [] { set_worker_threads_from_environment("KHZ_TEST_THREADS"); },
        "the environment variable KHZ_TEST_THREADS must be a whole number of threads ≥ 1, got"))
        << bad;
  }
  ASSERT_EQ(unsetenv("KHZ_TEST_THREADS"), 0);
  EXPECT_EQ(set_worker_threads_from_environment("KHZ_TEST_THREADS"), 0);
  EXPECT_EQ(worker_threads(), 2);
  set_worker_threads(0);
}

}  // namespace
}  // namespace khz::reduced
