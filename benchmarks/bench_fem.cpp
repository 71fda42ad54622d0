// Full FEM model throughput: R(u) and K(u) together (a Newton iteration's assembly), the
// internal forces alone and the strain energy alone, on ~10k tetrahedra (a 12×12×12 box, six per
// cube) and ~10k hexahedra (22×22×21), with 1 and 2 OpenMP threads (the argument).
#include <khz/reduced/fem/fem_model.hpp>
#include <khz/reduced/meshing/box_mesh.hpp>

#include <benchmark/benchmark.h>
#include <omp.h>

#include <random>

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
  omp_set_num_threads(static_cast<int>(state.range(0)));
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

constexpr auto tet = kr::ElementType::tetrahedron;
constexpr auto hex = kr::ElementType::hexahedron;

BENCHMARK_CAPTURE(forces_and_stiffness, tets, tet)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(forces_and_stiffness, hexes, hex)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(internal_forces, tets, tet)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(internal_forces, hexes, hex)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(strain_energy, tets, tet)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(strain_energy, hexes, hex)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond);

}  // namespace
