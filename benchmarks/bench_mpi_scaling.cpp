// Strong scaling of the reduced-polynomial precompute and of the modal derivatives over MPI
// ranks (issue 24). Run it under mpiexec with N ranks; in one launch it times, on the same mesh
// and basis (or modes):
//   - rank 0 alone on one thread (the other ranks sleep, not spin, meanwhile);
//   - all N ranks, one thread each, sharing the elements through khz::mpi::MpiWorkGroup;
//   - rank 0 alone on N threads: the same cores used by OpenMP instead of ranks.
// and prints speedup and parallel efficiency against the first, the shared result's largest
// relative difference from rank 0's own (round-off), the time per element and per element and
// r⁴ (the cost model docs/SCALING.md extrapolates from) and each rank's peak memory. The modal
// derivatives (the beam clamped at one end, k modes, k(k+1)/2 derivatives) get the same table,
// with the time per derivative, and the time with the factor distributed over the ranks by
// MUMPS (khz::mpi::MumpsFactorization) with its difference from rank 0's own.
//
//   mpiexec -n 2 --bind-to none bench_mpi_scaling [--cells 40] [--r 15,30] [--modes 10,20]
//                                                 [--quick]
//
// (Open MPI binds each of 2 ranks to one core by default, which would leave the N-thread run
// one core: --bind-to none.)

#include <khz/mpi/environment.hpp>
#include <khz/mpi/mpi_work_group.hpp>
#include <khz/mpi/mumps_factorization.hpp>
#include <khz/reduced/basis/linear_modes.hpp>
#include <khz/reduced/basis/modal_derivatives.hpp>
#include <khz/reduced/meshing/box_mesh.hpp>
#include <khz/reduced/solvers/fixed_dofs.hpp>
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

// Rank 0 alone runs `work` on `threads` threads, timed; the others wait asleep.
template <typename Work>
double alone(int threads, int rank, MPI_Comm communicator, const Work& work) {
  MPI_Barrier(communicator);
  double seconds = 0.0;
  if (rank == 0) {
    const ScopedWorkerThreads bound(threads);
    const auto start = Clock::now();
    work();
    seconds = std::chrono::duration<double>(Clock::now() - start).count();
  }
  sleeping_barrier(communicator);
  return seconds;
}

// Every rank runs `work` on one thread, timed from the first to the last rank's end.
template <typename Work>
double together(MPI_Comm communicator, const Work& work) {
  MPI_Barrier(communicator);
  const auto start = Clock::now();
  {
    const ScopedWorkerThreads bound(1);
    work();
  }
  MPI_Barrier(communicator);
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// The best of `repeats` interleaved runs of each kind (so that none is a cold first run): one
// rank on one thread, all ranks, one rank on as many threads as ranks.
struct Timings {
  double one = 1e300, distributed = 1e300, threads = 1e300;
};
template <typename Alone, typename Shared>
Timings best_of(int repeats, int ranks, int rank, MPI_Comm communicator, const Alone& run_alone,
                const Shared& run_shared) {
  Timings best;
  for (int repeat = 0; repeat < repeats; ++repeat) {
    best.one = std::min(best.one, alone(1, rank, communicator, run_alone));
    best.distributed = std::min(best.distributed, together(communicator, run_shared));
    best.threads = std::min(best.threads, alone(ranks, rank, communicator, run_alone));
  }
  return best;
}

double largest_column_difference(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  double worst = 0.0;
  for (Eigen::Index c = 0; c < b.cols(); ++c) {
    worst = std::max(worst, (a.col(c) - b.col(c)).norm() / b.col(c).norm());
  }
  return worst;
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
  CLI::App app{
      "Strong scaling of the reduced-polynomial precompute and the modal derivatives over MPI "
      "ranks"};
  int cells = 40;
  std::vector<int> dimensions{15, 30};
  std::vector<int> modes{10, 20};
  bool quick = false;
  int repeats = 2;
  app.add_option("--cells", cells, "Cells along the beam (cells/4 across): 6·cells³/16 tets");
  app.add_option("--r", dimensions, "Basis sizes r to time (comma-separated)")->delimiter(',');
  app.add_option("--modes", modes, "Mode counts k whose derivatives to time (comma-separated)")
      ->delimiter(',');
  app.add_option("--repeats", repeats, "Runs of each kind; the best is printed")
      ->check(CLI::PositiveNumber);
  app.add_flag("--quick", quick, "A small mesh and r = 6 (keeps the program working in CTest)");
  CLI11_PARSE(app, argc, argv);
  if (quick) {
    cells = 12;
    dimensions = {6};
    modes = {4};
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
    std::optional<ReducedModel> shared;
    const Timings t = best_of(
        repeats, ranks, rank, group.communicator(),
        [&] { single = ReducedModel::precompute(model, basis); },
        [&] {
          ReducedModelOptions options;
          options.group = &group;
          shared = ReducedModel::precompute(model, basis, options);
        });
    if (rank == 0) {
      const double r4 = std::pow(static_cast<double>(r), 4);
      std::printf("%4d %10.3f %10.3f %8.2f %9.0f%% %10.3f %8.2f %10.1e %12.0f %12.2f\n", r, t.one,
                  t.distributed, t.one / t.distributed, 100.0 * t.one / t.distributed / ranks,
                  t.threads, t.distributed / t.threads,
                  largest_relative_difference(*shared, *single), 1e9 * t.one / elements,
                  1e12 * t.one / elements / r4);
    }
  }

  // Modal derivatives of the beam clamped at x = 0: every rank factorizes K, each solves its
  // share of the right-hand-side blocks.
  const std::vector<int> clamped = vertices_in_box(
      model.mesh().vertices,
      Eigen::AlignedBox3d(Eigen::Vector3d(-1e-9, -1, -1), Eigen::Vector3d(1e-9, 1, 1)));
  if (rank == 0) {
    std::printf("\nmodal derivatives, %d ranks, the beam clamped at one end\n", ranks);
    std::printf("%4s %6s %10s %10s %8s %10s %10s %8s %10s %12s %10s %10s\n", "k", "derivs",
                "1 rank s", "ranks s", "speedup", "efficiency", "threads s", "rk/thr", "rel diff",
                "ms/deriv", "MUMPS s", "MUMPS diff");
  }
  for (const int k : modes) {
    LinearModesOptions mode_options;
    mode_options.num_modes = k;
    const LinearModes linear = compute_linear_modes(model, clamped, mode_options);
    ModalDerivatives single;
    ModalDerivatives shared;
    const Timings t = best_of(
        repeats, ranks, rank, group.communicator(),
        [&] { single = compute_modal_derivatives(model, linear); },
        [&] {
          ModalDerivativesOptions options;
          options.group = &group;
          shared = compute_modal_derivatives(model, linear, options);
        });
    // The factor distributed over the ranks by MUMPS: every rank in every solve.
    ModalDerivatives distributed;
    double mumps = 1e300;
    for (int repeat = 0; repeat < repeats; ++repeat) {
      mumps = std::min(mumps, together(group.communicator(), [&] {
                         ModalDerivativesOptions options;
                         options.group = &group;
                         options.factorize =
                             khz::mpi::MumpsFactorization::factorize(group.communicator());
                         distributed = compute_modal_derivatives(model, linear, options);
                       }));
    }
    if (rank == 0) {
      const auto count = static_cast<double>(single.vectors.cols());
      std::printf(
          "%4d %6.0f %10.3f %10.3f %8.2f %9.0f%% %10.3f %8.2f %10.1e %12.2f %10.3f %10.1e\n", k,
          count, t.one, t.distributed, t.one / t.distributed, 100.0 * t.one / t.distributed / ranks,
          t.threads, t.distributed / t.threads,
          largest_column_difference(shared.vectors, single.vectors), 1e3 * t.one / count, mumps,
          largest_column_difference(distributed.vectors, single.vectors));
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
