// Full FEM model throughput: R(u) and K(u) together (a Newton iteration's assembly), the
// internal forces alone and the strain energy alone, on ~10k tetrahedra (a 12×12×12 box, six per
// cube) and ~10k hexahedra (22×22×21), on 1 and 2 worker threads (the argument). And a whole
// nonlinear static solve (assembly, CHOLMOD, OpenBLAS) under worker_threads() of 1, 2 and 4, with
// the context switches per solve: 4 oversubscribes a 2-core machine, as CHOLMOD's 4 OpenMP
// threads did before the setting bounded them.
#include <khz/reduced/fem/fem_model.hpp>
#include <khz/reduced/meshing/box_mesh.hpp>
#include <khz/reduced/solvers/static_solver.hpp>
#include <khz/reduced/worker_threads.hpp>

#include <benchmark/benchmark.h>
#include <sys/resource.h>

#include <random>
#include <vector>

namespace {

namespace kr = khz::reduced;

const kr::FemModel& model(kr::ElementType type) {
  static const kr::Material material = kr::Material::stvk(1e6, 0.45, 1000.0);
  static const kr::FemModel tets(kr::box_tet_mesh({0, 0, 0}, {1, 1, 1}, {12, 12, 12}), {material});
  static const kr::FemModel hexes(kr::box_hex_mesh({0, 0, 0}, {1, 1, 21.0 / 22.0}, {22, 22, 21}),
                                  {material});
  return type == kr::ElementType::tetrahedron ? tets : hexes;
}

/// A large deformation: a twist about the z axis plus random noise of 1% of the box.
Eigen::VectorXd deformation(const kr::FemModel& fem) {
  const kr::VolumeMesh& mesh = fem.mesh();
  std::mt19937 random(1);
  std::uniform_real_distribution<double> noise(-0.01, 0.01);
  Eigen::VectorXd u(fem.num_dofs());
  for (Eigen::Index v = 0; v < mesh.num_vertices(); ++v) {
    const Eigen::Vector3d x = mesh.vertices.row(v).transpose();
    const double angle = 0.8 * x.z();
    const Eigen::Vector2d centred(x.x() - 0.5, x.y() - 0.5);
    u.segment<3>(3 * v) << std::cos(angle) * centred.x() - std::sin(angle) * centred.y() -
                               centred.x() + noise(random),
        std::sin(angle) * centred.x() + std::cos(angle) * centred.y() - centred.y() + noise(random),
        noise(random);
  }
  return u;
}

void set_up(benchmark::State& state, const kr::FemModel& fem) {
  kr::set_worker_threads(static_cast<int>(state.range(0)));
  state.counters["threads"] = static_cast<double>(state.range(0));
  state.counters["elements"] = static_cast<double>(fem.mesh().num_elements());
  state.counters["vertices"] = static_cast<double>(fem.mesh().num_vertices());
}

void forces_and_stiffness(benchmark::State& state, kr::ElementType type) {
  const kr::FemModel& fem = model(type);
  set_up(state, fem);
  const Eigen::VectorXd u = deformation(fem);
  Eigen::VectorXd forces;
  kr::SparseMatrix stiffness = fem.stiffness_pattern();
  for (auto _ : state) {
    fem.forces_and_stiffness(u, forces, stiffness);
    benchmark::DoNotOptimize(stiffness.valuePtr());
    benchmark::DoNotOptimize(forces.data());
  }
  state.counters["nonzeros"] = static_cast<double>(stiffness.nonZeros());
}

void internal_forces(benchmark::State& state, kr::ElementType type) {
  const kr::FemModel& fem = model(type);
  set_up(state, fem);
  const Eigen::VectorXd u = deformation(fem);
  Eigen::VectorXd forces;
  for (auto _ : state) {
    fem.internal_forces(u, forces);
    benchmark::DoNotOptimize(forces.data());
  }
}

void strain_energy(benchmark::State& state, kr::ElementType type) {
  const kr::FemModel& fem = model(type);
  set_up(state, fem);
  const Eigen::VectorXd u = deformation(fem);
  for (auto _ : state) benchmark::DoNotOptimize(fem.strain_energy(u));
}

/// A 1 m × 0.1 m × 0.1 m cantilever of 6×6×60 hexahedra (9k dofs), clamped at x = 0 and bent
/// under a tip load, in two load steps.
void static_solve(benchmark::State& state) {
  const kr::ScopedWorkerThreads threads(static_cast<int>(state.range(0)));
  static const kr::FemModel beam(kr::box_hex_mesh({0, 0, 0}, {1.0, 0.1, 0.1}, {60, 6, 6}),
                                 {kr::Material::stvk(1e7, 0.3, 1000.0)});
  std::vector<int> clamped, tip;
  for (Eigen::Index v = 0; v < beam.mesh().num_vertices(); ++v) {
    const double x = beam.mesh().vertices(v, 0);
    if (x < 1e-9) clamped.push_back(static_cast<int>(v));
    if (x > 1.0 - 1e-9) tip.push_back(static_cast<int>(v));
  }
  Eigen::VectorXd load = Eigen::VectorXd::Zero(beam.num_dofs());
  for (const int v : tip) load[3 * v + 2] = -10.0 / static_cast<double>(tip.size());
  kr::StaticSolveOptions options;
  options.load_steps = 2;
  const auto context_switches = [] {
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    return static_cast<double>(usage.ru_nvcsw + usage.ru_nivcsw);
  };
  const double switches_before = context_switches();
  for (auto _ : state) {
    const kr::StaticSolution solution = kr::solve_static(beam, clamped, load, options);
    benchmark::DoNotOptimize(solution.displacement.data());
  }
  state.counters["context_switches"] =
      benchmark::Counter(context_switches() - switches_before, benchmark::Counter::kAvgIterations);
  state.counters["threads"] = static_cast<double>(state.range(0));
  state.counters["dofs"] = static_cast<double>(beam.num_dofs());
}

constexpr auto tet = kr::ElementType::tetrahedron;
constexpr auto hex = kr::ElementType::hexahedron;

BENCHMARK_CAPTURE(forces_and_stiffness, tets, tet)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(forces_and_stiffness, hexes, hex)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(internal_forces, tets, tet)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(internal_forces, hexes, hex)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(strain_energy, tets, tet)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(strain_energy, hexes, hex)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond);
BENCHMARK(static_solve)->Arg(1)->Arg(2)->Arg(4)->Unit(benchmark::kSecond)->UseRealTime();

}  // namespace
