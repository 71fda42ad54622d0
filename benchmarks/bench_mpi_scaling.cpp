// Strong scaling of the reduced-polynomial precompute over MPI ranks (issue 24). Run it under
// mpiexec with N ranks; in one launch it times, on the same mesh and basis:
//   - rank 0 alone on one thread (the other ranks sleep, not spin, meanwhile);
//   - all N ranks, one thread each, sharing the elements through khz::mpi::MpiWorkGroup;
//   - rank 0 alone on N threads: the same cores used by OpenMP instead of ranks.
// and prints speedup and parallel efficiency against the first, the shared result's largest
// relative difference from rank 0's own (round-off), the time per element and per element and
// r⁴ (the cost model docs/SCALING.md extrapolates from) and each rank's peak memory.
//
//   mpiexec -n 2 --bind-to none bench_mpi_scaling [--cells 40] [--r 15,30] [--quick]
//
// (Open MPI binds each of 2 ranks to one core by default, which would leave the N-thread run
// one core: --bind-to none.)

#include <khz/mpi/environment.hpp>
#include <khz/mpi/mpi_work_group.hpp>
#include <khz/reduced/meshing/box_mesh.hpp>
#include <khz/reduced/subspace/reduced_model.hpp>
#include <khz/reduced/worker_threads.hpp>

#include "random_basis.hpp"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include <sched.h>

namespace {

using namespace khz::reduced;
using Clock = std::chrono::steady_clock;

// A 4:1:1 beam of cells × cells/4 × cells/4 cubes, six tetrahedra each.
FemModel beam(int cells) {
  const int across = std::max(1, cells / 4);
  return FemModel(box_tet_mesh(Eigen::Vector3d::Zero(), Eigen::Vector3d(0.4, 0.1, 0.1),
                               Eigen::Vector3i(cells, across, across)),
                  {Material::stvk(1e6, 0.45, 1000.0)});
}

// Waits for every rank at a barrier while sleeping between polls, so that a rank with nothing
// to do leaves its core to the one that works (MPI_Barrier spins).
void sleeping_barrier(MPI_Comm communicator) {
  MPI_Request request = MPI_REQUEST_NULL;
  MPI_Ibarrier(communicator, &request);
  int done = 0;
  while (true) {
    MPI_Test(&request, &done, MPI_STATUS_IGNORE);
    if (done) return;
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
}

// Rank 0's precompute alone on `threads` threads, timed; the others wait asleep.
double alone(const FemModel& model, const Basis& basis, int threads, int rank,
             MPI_Comm communicator, std::optional<ReducedModel>& result) {
  MPI_Barrier(communicator);
  double seconds = 0.0;
  if (rank == 0) {
    const ScopedWorkerThreads bound(threads);
    const auto start = Clock::now();
    result = ReducedModel::precompute(model, basis);
    seconds = std::chrono::duration<double>(Clock::now() - start).count();
  }
  sleeping_barrier(communicator);
  return seconds;
}

double largest_relative_difference(const ReducedModel& a, const ReducedModel& b) {
  double worst = 0.0;
  for (std::size_t p = 0; p < a.groups()[0].parts.size(); ++p) {
    const EnergyPolynomial& x = a.groups()[0].parts[p];
    const EnergyPolynomial& y = b.groups()[0].parts[p];
    worst = std::max({worst, (x.quartic - y.quartic).norm() / y.quartic.norm(),
                      (x.cubic - y.cubic).norm() / y.cubic.norm(),
                      (x.quadratic - y.quadratic).norm() / y.quadratic.norm()});
  }
  return worst;
}

// Peak resident memory of this process (MB), from /proc/self/status.
double peak_memory_mb() {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line)) {
    if (line.rfind("VmHWM:", 0) == 0) return std::stod(line.substr(6)) / 1024.0;
  }
  return 0.0;
}

}  // namespace

int main(int argc, char** argv) {
  const khz::mpi::Environment mpi(argc, argv);
  CLI::App app{"Strong scaling of the reduced-polynomial precompute over MPI ranks"};
  int cells = 40;
  std::vector<int> dimensions{15, 30};
  bool quick = false;
  int repeats = 2;
  app.add_option("--cells", cells, "Cells along the beam (cells/4 across): 6·cells³/16 tets");
  app.add_option("--r", dimensions, "Basis sizes r to time (comma-separated)")->delimiter(',');
  app.add_option("--repeats", repeats, "Runs of each kind; the best is printed")
      ->check(CLI::PositiveNumber);
  app.add_flag("--quick", quick, "A small mesh and r = 6 (keeps the program working in CTest)");
  CLI11_PARSE(app, argc, argv);
  if (quick) {
    cells = 12;
    dimensions = {6};
    repeats = 1;
  }

  khz::mpi::MpiWorkGroup group;
  const int rank = group.rank();
  const int ranks = group.size();
  const FemModel model = beam(cells);
  const auto elements = static_cast<double>(model.mesh().elements.rows());
  if (rank == 0) {
    std::printf("reduced polynomials, %d ranks, %.0f tetrahedra (%d dofs)\n", ranks, elements,
                static_cast<int>(model.num_dofs()));
    cpu_set_t cores;
    if (sched_getaffinity(0, sizeof(cores), &cores) == 0 && CPU_COUNT(&cores) < ranks) {
      std::printf(
          "note: rank 0 may run on %d core(s) only, so its %d-thread run shares them "
          "(Open MPI: --bind-to none)\n",
          CPU_COUNT(&cores), ranks);
    }
    std::printf("%4s %10s %10s %8s %10s %10s %8s %10s %12s %12s\n", "r", "1 rank s", "ranks s",
                "speedup", "efficiency", "threads s", "rk/thr", "rel diff", "ns/element",
                "ps/el/r^4");
  }
  for (const int r : dimensions) {
    const Basis basis = khz::bench::random_basis(model, r);
    std::optional<ReducedModel> single;
    std::optional<ReducedModel> threaded;
    std::optional<ReducedModel> shared;
    // Each figure is the best of `repeats` runs, interleaved, so that none is a cold first run.
    double one = 1e300, distributed = 1e300, threads = 1e300;
    for (int repeat = 0; repeat < repeats; ++repeat) {
      one = std::min(one, alone(model, basis, 1, rank, group.communicator(), single));

      MPI_Barrier(group.communicator());
      const auto start = Clock::now();
      {
        const ScopedWorkerThreads bound(1);
        ReducedModelOptions options;
        options.group = &group;
        shared = ReducedModel::precompute(model, basis, options);
      }
      MPI_Barrier(group.communicator());
      distributed =
          std::min(distributed, std::chrono::duration<double>(Clock::now() - start).count());

      threads = std::min(threads, alone(model, basis, ranks, rank, group.communicator(), threaded));
    }
    if (rank == 0) {
      const double r4 = std::pow(static_cast<double>(r), 4);
      std::printf("%4d %10.3f %10.3f %8.2f %9.0f%% %10.3f %8.2f %10.1e %12.0f %12.2f\n", r, one,
                  distributed, one / distributed, 100.0 * one / distributed / ranks, threads,
                  distributed / threads, largest_relative_difference(*shared, *single),
                  1e9 * one / elements, 1e12 * one / elements / r4);
    }
  }
  // Every rank's peak memory, printed by rank 0 in rank order.
  std::vector<double> memory(static_cast<std::size_t>(ranks), 0.0);
  memory[static_cast<std::size_t>(rank)] = peak_memory_mb();
  group.sum(memory);
  if (rank == 0) {
    std::printf("peak memory per rank (MB):");
    for (const double mb : memory) std::printf(" %.0f", mb);
    std::printf("\n");
  }
  return 0;
}
