// Precompute cost of reduced energy polynomials (issue target: r = 30 on ~11k tetrahedra in
// ≤ 2 s on 2 cores; the thesis reports 79 minutes for r = 30 on 11,304 elements, Fig. 2.8).
// The basis is random: the cost does not depend on its values, only on r and the mesh.

#include <khz/reduced/meshing/box_mesh.hpp>
#include <khz/reduced/subspace/reduced_model.hpp>

#include "random_basis.hpp"

#include <benchmark/benchmark.h>

namespace {

using namespace khz::reduced;

// 1920 cells × 6 = 11,520 tetrahedra (or 1920 hexahedra), a 4:1.5:1.5 beam.
FemModel beam(bool hexahedra) {
  const Eigen::Vector3d lo = Eigen::Vector3d::Zero(), hi(0.4, 0.15, 0.15);
  const Eigen::Vector3i cells(32, 6, 10);
  return FemModel(hexahedra ? box_hex_mesh(lo, hi, cells) : box_tet_mesh(lo, hi, cells),
                  {Material::stvk(1e6, 0.45, 1000.0)});
}

void precompute(benchmark::State& state, bool hexahedra) {
  const FemModel model = beam(hexahedra);
  const Basis basis = khz::bench::random_basis(model, state.range(0));
  for (auto _ : state) {
    const ReducedModel reduced = ReducedModel::precompute(model, basis);
    benchmark::DoNotOptimize(reduced.groups().front().parts.front().quartic.data());
  }
  state.counters["elements"] = static_cast<double>(model.mesh().elements.rows());
  state.counters["r"] = static_cast<double>(state.range(0));
}

void BM_PrecomputeTetrahedra(benchmark::State& state) { precompute(state, false); }
void BM_PrecomputeHexahedra(benchmark::State& state) { precompute(state, true); }

BENCHMARK(BM_PrecomputeTetrahedra)
    ->Arg(15)
    ->Arg(30)
    ->Arg(60)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(1);
BENCHMARK(BM_PrecomputeHexahedra)
    ->Arg(30)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(1);

}  // namespace
