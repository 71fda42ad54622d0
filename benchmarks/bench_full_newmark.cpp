// One implicit Newmark step of the full model (the reference integrator) on ~10k tetrahedra:
// a 1 m × 0.25 m × 0.25 m steel beam of 30×8×8 cubes × 6 = 11,520 tets, clamped at x = 0,
// under a tip load. Each step runs Newton to convergence: assemble R and K, factor with
// CHOLMOD, solve.
#include <khz/reduced/fem/fem_model.hpp>
#include <khz/reduced/meshing/box_mesh.hpp>
#include <khz/reduced/solvers/fixed_dofs.hpp>
#include <khz/reduced/solvers/full_newmark.hpp>

#include <benchmark/benchmark.h>

#include <Eigen/Geometry>

namespace {

namespace kr = khz::reduced;

void BM_FullNewmarkStep(benchmark::State& state) {
  const Eigen::Vector3d size(1.0, 0.25, 0.25);
  const kr::FemModel model(
      kr::box_tet_mesh(Eigen::Vector3d::Zero(), size, Eigen::Vector3i(30, 8, 8)),
      {kr::Material::stvk(200e9, 0.3, 7800.0)});
  const Eigen::AlignedBox3d clamp_face(Eigen::Vector3d(-1e-9, -1, -1), Eigen::Vector3d(1e-9, 1, 1));
  const std::vector<int> clamped = kr::vertices_in_box(model.mesh().vertices, clamp_face);
  kr::FullNewmarkOptions options;
  options.newmark.time_step = 1e-4;
  options.newmark.stiffness_damping = 1e-5;
  kr::FullNewmark integrator(model, clamped, options);
  Eigen::VectorXd load = Eigen::VectorXd::Zero(model.num_dofs());
  for (Eigen::Index v = 0; v < model.mesh().num_vertices(); ++v) {
    if (model.mesh().vertices(v, 0) > size.x() - 1e-9) load[3 * v + 2] = -1e3;
  }
  int iterations = 0;
  for (auto _ : state) iterations += integrator.step(load).iterations;
  state.counters["tets"] = static_cast<double>(model.mesh().num_elements());
  state.counters["dofs"] = static_cast<double>(model.num_dofs());
  state.counters["newton_per_step"] =
      static_cast<double>(iterations) / static_cast<double>(state.iterations());
}

BENCHMARK(BM_FullNewmarkStep)->Unit(benchmark::kMillisecond);

}  // namespace
