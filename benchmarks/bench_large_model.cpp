// How large a reduced model one machine prepares (issue 24, item 5): a 4:1:1 beam of tetrahedra
// clamped at one end taken through the whole pipeline at basis size r (FEM set-up, k linear
// modes, their modal derivatives, mass-PCA to r, the reduced polynomials), printing each stage's
// wall time and the process's peak memory after it. docs/SCALING.md extrapolates from these.
//
//   bench_large_model [--cells 120] [--r 30] [--modes 10]      (6·cells³/16 tetrahedra)

#include <khz/reduced/basis/modal_derivative_basis.hpp>
#include <khz/reduced/fem/fem_model.hpp>
#include <khz/reduced/meshing/box_mesh.hpp>
#include <khz/reduced/solvers/fixed_dofs.hpp>
#include <khz/reduced/subspace/reduced_model.hpp>
#include <khz/reduced/worker_threads.hpp>

#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <string>

namespace {

using namespace khz::reduced;
using Clock = std::chrono::steady_clock;

// Peak resident memory of this process so far (GB), from /proc/self/status.
double peak_memory_gb() {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line)) {
    if (line.rfind("VmHWM:", 0) == 0) return std::stod(line.substr(6)) / (1024.0 * 1024.0);
  }
  return 0.0;
}

// Prints one stage's time since `start` and the peak memory so far; restarts the clock.
void stage_done(const char* name, Clock::time_point& start) {
  const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
  std::printf("  %-22s %9.1f s   peak %6.2f GB\n", name, seconds, peak_memory_gb());
  std::fflush(stdout);
  start = Clock::now();
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"A reduced model as large as one machine prepares: time and peak memory per stage"};
  int cells = 120;
  int r = 30;
  int k = 10;
  app.add_option("--cells", cells, "Cells along the beam (cells/4 across): 6·cells³/16 tets")
      ->check(CLI::Range(4, 4000));
  app.add_option("--r", r, "Basis size r")->check(CLI::Range(1, 200));
  app.add_option("--modes", k, "Linear modes k (k(k+1)/2 derivatives)")->check(CLI::Range(1, 100));
  CLI11_PARSE(app, argc, argv);

  auto start = Clock::now();
  const auto total_start = start;
  const int across = std::max(1, cells / 4);
  const FemModel model(box_tet_mesh(Eigen::Vector3d::Zero(), Eigen::Vector3d(0.4, 0.1, 0.1),
                                    Eigen::Vector3i(cells, across, across)),
                       {Material::stvk(1e6, 0.45, 1000.0)});
  std::printf("beam of %lld tetrahedra, %lld dofs, r = %d, k = %d, %d threads\n",
              static_cast<long long>(model.mesh().elements.rows()),
              static_cast<long long>(model.num_dofs()), r, k, worker_threads());
  stage_done("mesh and FEM set-up", start);
  const std::vector<int> clamped = vertices_in_box(
      model.mesh().vertices,
      Eigen::AlignedBox3d(Eigen::Vector3d(-1e-9, -1, -1), Eigen::Vector3d(1e-9, 1, 1)));
  ModalDerivativeBasisOptions options;
  options.basis_size = r;
  options.modes.num_modes = k;
  std::string current;
  options.progress = [&](const Progress& progress) {
    if (progress.stage != current) {
      if (!current.empty()) stage_done(current.c_str(), start);
      current = std::string(progress.stage);
    }
    return true;
  };
  Basis basis = modal_derivative_basis(model, clamped, options);
  stage_done(current.c_str(), start);
  const ReducedModel reduced = ReducedModel::precompute(model, std::move(basis));
  stage_done("reduced polynomials", start);
  std::printf("total %.1f s, peak memory %.2f GB\n",
              std::chrono::duration<double>(Clock::now() - total_start).count(), peak_memory_gb());
  return reduced.dimension() == r ? 0 : 1;
}
