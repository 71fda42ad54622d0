// One implicit Newmark step of a reduced model with one Newton iteration (R̃ and K̃ evaluation,
// the r×r solve and the state update), the per-step cost a haptic loop pays (thesis §2.9,
// Fig. 2.9). Issue targets on one core: r=15 ≤ 2 µs, r=30 ≤ 15 µs, r=60 ≤ 300 µs.
//
// The model is real: a clamped rubber beam with a modal-derivative basis of 60 vectors, its
// polynomials precomputed once and truncated to each r (thesis §2.11). The state is a large
// deformation, reached by stepping under a tip load first, so the timed steps do the work of an
// interactive simulation (the cost does not depend on q, but the solve path does: Cholesky).

#include <khz/reduced/basis/modal_derivative_basis.hpp>
#include <khz/reduced/meshing/box_mesh.hpp>
#include <khz/reduced/solvers/fixed_dofs.hpp>
#include <khz/reduced/subspace/polynomial_forces.hpp>
#include <khz/reduced/subspace/reduced_model.hpp>
#include <khz/reduced/subspace/reduced_newmark.hpp>

#include <benchmark/benchmark.h>

#include <omp.h>

namespace {

using namespace khz::reduced;

struct BeamModel {
  ReducedModel model;
  Eigen::VectorXd tip_load;  // full 3n
};

const BeamModel& beam_model() {
  static const BeamModel beam = [] {
    const double length = 0.4, side = 0.04;
    const FemModel fem(box_hex_mesh(Eigen::Vector3d::Zero(), Eigen::Vector3d(length, side, side),
                                    Eigen::Vector3i(20, 3, 3)),
                       {Material::stvk(1.5e7, 0.45, 1000.0)});
    const auto face = [&](double x) {
      return vertices_in_box(
          fem.mesh().vertices,
          Eigen::AlignedBox3d(Eigen::Vector3d(x - 1e-9, -1e-9, -1e-9),
                              Eigen::Vector3d(x + 1e-9, side + 1e-9, side + 1e-9)));
    };
    ModalDerivativeBasisOptions options;
    options.modes.num_modes = 12;
    options.basis_size = 60;
    Basis basis = modal_derivative_basis(fem, face(0.0), options);
    Eigen::VectorXd load = Eigen::VectorXd::Zero(fem.num_dofs());
    const std::vector<int> tip = face(length);
    for (int v : tip) load[3 * v + 1] = 20.0 / static_cast<double>(tip.size());
    return BeamModel{ReducedModel::precompute(fem, std::move(basis)), load};
  }();
  return beam;
}

void BM_ReducedNewmarkStep(benchmark::State& state) {
  omp_set_num_threads(1);
  const auto r = static_cast<Eigen::Index>(state.range(0));
  const ReducedModel model = beam_model().model.truncated(r);
  PolynomialForces forces(model.energy_polynomial());
  ReducedNewmarkOptions options;
  options.max_newton_iterations = 1;
  const auto integrator = make_reduced_newmark(forces, model.mass(), options);
  const Eigen::VectorXd load = model.basis().vectors.transpose() * beam_model().tip_load;
  for (int step = 0; step < 100; ++step) integrator->step(load);  // deform the beam

  for (auto _ : state) {
    const ReducedStepReport report = integrator->step(load);
    benchmark::DoNotOptimize(report);
  }
  state.counters["r"] = static_cast<double>(r);
}

BENCHMARK(BM_ReducedNewmarkStep)
    ->Arg(5)
    ->Arg(10)
    ->Arg(15)
    ->Arg(20)
    ->Arg(30)
    ->Arg(45)
    ->Arg(60)
    ->Unit(benchmark::kMicrosecond);

}  // namespace
