// Basis generation on a ~20k-vertex tetrahedral mesh (thesis §2.8, issue targets: 20 modes
// ≤ 5 s, all 210 derivatives ≤ 15 s, mass-PCA to r = 30 ≤ 2 s): CGAL's dino.off meshed by
// Mesh_3, anchored at its feet, StVK with a rubber-like material.
#include <khz/reduced/basis/linear_modes.hpp>
#include <khz/reduced/basis/mass_pca.hpp>
#include <khz/reduced/basis/modal_derivative_basis.hpp>
#include <khz/reduced/basis/modal_derivatives.hpp>
#include <khz/reduced/io/mesh_file.hpp>
#include <khz/reduced/meshing/tetrahedralize.hpp>
#include <khz/reduced/solvers/fixed_dofs.hpp>

#include <benchmark/benchmark.h>

#include <Eigen/Geometry>

#include <chrono>
#include <filesystem>
#include <memory>
#include <vector>

namespace {

namespace kr = khz::reduced;

constexpr int kModes = 20;
constexpr int kBasisSize = 30;

struct Scene {
  kr::FemModel model;
  std::vector<int> anchors;
};

// Built once and shared by the benchmarks (meshing alone takes seconds).
const Scene& dino() {
  static const std::unique_ptr<Scene> scene = [] {
    const kr::TriangleMesh surface =
        kr::read_triangle_mesh(std::filesystem::path(KHZ_CGAL_MESH_DIR) / "dino.off");
    const Eigen::AlignedBox3d bounds(surface.vertices.colwise().minCoeff().transpose(),
                                     surface.vertices.colwise().maxCoeff().transpose());
    kr::TetrahedralizeOptions options;
    options.facet_size = bounds.diagonal().norm() / 75.0;
    options.facet_distance = bounds.diagonal().norm() / 2500.0;
    kr::VolumeMesh mesh = kr::tetrahedralize(surface, options);
    // The feet: vertices within 2 % of the height above the lowest point (y is up).
    Eigen::AlignedBox3d feet = bounds;
    feet.max().y() = bounds.min().y() + 0.02 * bounds.sizes().y();
    feet.min().y() -= 1.0;
    std::vector<int> anchors = kr::vertices_in_box(mesh.vertices, feet);
    return std::make_unique<Scene>(
        Scene{kr::FemModel(std::move(mesh), {kr::Material::stvk(1e6, 0.45, 1100.0)}),
              std::move(anchors)});
  }();
  return *scene;
}

void report_sizes(benchmark::State& state, const Scene& scene) {
  state.counters["vertices"] = static_cast<double>(scene.model.mesh().num_vertices());
  state.counters["tets"] = static_cast<double>(scene.model.mesh().num_elements());
  state.counters["anchors"] = static_cast<double>(scene.anchors.size());
}

kr::LinearModes modes_of(const Scene& scene) {
  kr::LinearModesOptions options;
  options.num_modes = kModes;
  return kr::compute_linear_modes(scene.model, scene.anchors, options);
}

void BM_LinearModes(benchmark::State& state) {
  const Scene& scene = dino();
  kr::LinearModes modes;
  for (auto _ : state) modes = modes_of(scene);
  report_sizes(state, scene);
  state.counters["modes"] = kModes;
  state.counters["solves"] = modes.solves;
  state.counters["f1_hz"] = modes.frequencies_hz()(0);
  state.counters["f20_hz"] = modes.frequencies_hz()(kModes - 1);
}
BENCHMARK(BM_LinearModes)->Unit(benchmark::kSecond)->Iterations(1)->UseRealTime();

void BM_ModalDerivatives(benchmark::State& state) {
  const Scene& scene = dino();
  const kr::LinearModes modes = modes_of(scene);
  kr::ModalDerivatives derivatives;
  for (auto _ : state) derivatives = kr::compute_modal_derivatives(scene.model, modes);
  report_sizes(state, scene);
  state.counters["derivatives"] = static_cast<double>(derivatives.vectors.cols());
}
BENCHMARK(BM_ModalDerivatives)->Unit(benchmark::kSecond)->Iterations(1)->UseRealTime();

// The same dino, free-floating: 6 rigid modes apart, then eq. 2.60 by deflated MINRES for
// every ordered pair of the first 10 deformation modes (100 derivatives). Issue 23's target:
// 5 s where the anchored 210 took 2.2 s, so ratio_to_anchored (the anchored dino's 210
// derivatives, timed in the same run) ≤ 2.27; it was 11.2 (24.6 s) before deflation.
void BM_FreeModalDerivatives(benchmark::State& state) {
  const Scene& scene = dino();
  kr::LinearModesOptions options;
  options.num_modes = 10;
  const kr::LinearModes modes = kr::compute_linear_modes(scene.model, {}, options);
  const kr::LinearModes anchored_modes = modes_of(scene);
  const auto start = std::chrono::steady_clock::now();
  benchmark::DoNotOptimize(kr::compute_modal_derivatives(scene.model, anchored_modes));
  const std::chrono::duration<double> anchored = std::chrono::steady_clock::now() - start;
  kr::ModalDerivatives derivatives;
  double seconds = 0.0;
  for (auto _ : state) {
    const auto free_start = std::chrono::steady_clock::now();
    derivatives = kr::compute_modal_derivatives(scene.model, modes);
    seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - free_start).count();
  }
  report_sizes(state, scene);
  state.counters["derivatives"] = static_cast<double>(derivatives.vectors.cols());
  state.counters["minres_iterations"] = derivatives.max_minres_iterations;
  state.counters["anchored_s"] = anchored.count();
  state.counters["ratio_to_anchored"] = seconds / anchored.count();
}
BENCHMARK(BM_FreeModalDerivatives)->Unit(benchmark::kSecond)->Iterations(1)->UseRealTime();

void BM_MassPca(benchmark::State& state) {
  const Scene& scene = dino();
  const kr::LinearModes modes = modes_of(scene);
  const kr::ModalDerivatives derivatives = kr::compute_modal_derivatives(scene.model, modes);
  const kr::SparseMatrix mass = scene.model.mass_matrix();
  const Eigen::MatrixXd samples = kr::weighted_modal_samples(modes, derivatives, mass);
  kr::PcaOptions options;
  options.basis_size = kBasisSize;
  options.metric = static_cast<kr::PcaMetric>(state.range(0));
  kr::PcaResult result;
  for (auto _ : state) result = kr::principal_components(samples, mass, options);
  report_sizes(state, scene);
  state.counters["samples"] = static_cast<double>(samples.cols());
  state.counters["r"] = kBasisSize;
  // Fraction of the samples' squared mass norm the basis misses.
  state.counters["discarded"] =
      result.singular_values.tail(result.singular_values.size() - kBasisSize).squaredNorm() /
      result.singular_values.squaredNorm();
}
BENCHMARK(BM_MassPca)
    ->Arg(static_cast<int>(kr::PcaMetric::mass))
    ->Arg(static_cast<int>(kr::PcaMetric::lumped_mass))
    ->ArgName("metric")
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace
