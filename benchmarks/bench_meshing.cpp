// Volumetric meshing: CGAL Mesh_3 tetrahedralization of dino.off with the default criteria
// (~20k tetrahedra), and voxelization (thesis §2.5.2) of ChineseDragon-10kv.off (20k triangles).
#include <khz/reduced/io/mesh_file.hpp>
#include <khz/reduced/mesh/element_quality.hpp>
#include <khz/reduced/mesh/mesh_report.hpp>
#include <khz/reduced/meshing/tetrahedralize.hpp>
#include <khz/reduced/meshing/voxelize.hpp>

#include <benchmark/benchmark.h>

#include <filesystem>
#include <numbers>
#include <string>

namespace {

namespace kr = khz::reduced;

kr::TriangleMesh cgal_mesh(const std::string& name) {
  return kr::read_triangle_mesh(std::filesystem::path(KHZ_CGAL_MESH_DIR) / name);
}

void BM_TetrahedralizeDino(benchmark::State& state) {
  const kr::TriangleMesh dino = cgal_mesh("dino.off");
  kr::VolumeMesh mesh;
  for (auto _ : state) {
    mesh = kr::tetrahedralize(dino);
    benchmark::DoNotOptimize(mesh.elements.data());
  }
  const kr::QualityReport quality = kr::analyze_elements(mesh);
  state.counters["tets"] = static_cast<double>(mesh.num_elements());
  state.counters["vertices"] = static_cast<double>(mesh.num_vertices());
  // Meshed over enclosed volume: the inscribed boundary loses a little.
  state.counters["volume_ratio"] = quality.total_volume / kr::analyze_mesh(dino).signed_volume;
  state.counters["min_dihedral_deg"] = quality.min_quality * 180 / std::numbers::pi;
}
BENCHMARK(BM_TetrahedralizeDino)->Unit(benchmark::kMillisecond)->Iterations(3);

// Arguments: resolution, fill_interior.
void BM_VoxelizeDragon(benchmark::State& state) {
  const kr::TriangleMesh dragon = cgal_mesh("ChineseDragon-10kv.off");
  kr::VoxelizeOptions options;
  options.resolution = static_cast<int>(state.range(0));
  options.fill_interior = state.range(1) != 0;
  kr::VolumeMesh mesh;
  for (auto _ : state) {
    mesh = kr::voxelize(dragon, options);
    benchmark::DoNotOptimize(mesh.elements.data());
  }
  state.counters["voxels"] = static_cast<double>(mesh.num_elements());
  state.counters["vertices"] = static_cast<double>(mesh.num_vertices());
}
BENCHMARK(BM_VoxelizeDragon)
    ->Args({64, 0})
    ->Args({64, 1})
    ->Args({128, 0})
    ->Args({128, 1})
    ->ArgNames({"resolution", "fill"})
    ->Unit(benchmark::kMillisecond);

}  // namespace
