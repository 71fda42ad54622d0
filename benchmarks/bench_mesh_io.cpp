// Mesh I/O throughput: parse each format from memory, and analyze_mesh, on CGAL's
// ChineseDragon-10kv.off (10k vertices, 20k triangles) converted in memory to every format.
#include <khz/reduced/io/mesh_file.hpp>
#include <khz/reduced/io/obj.hpp>
#include <khz/reduced/io/off.hpp>
#include <khz/reduced/io/ply.hpp>
#include <khz/reduced/io/stl.hpp>
#include <khz/reduced/mesh/mesh_report.hpp>

#include <benchmark/benchmark.h>

#include <filesystem>
#include <functional>
#include <string>

namespace {

namespace kr = khz::reduced;

const kr::TriangleMesh& dragon() {
  static const kr::TriangleMesh mesh =
      kr::read_triangle_mesh(std::filesystem::path(KHZ_CGAL_MESH_DIR) / "ChineseDragon-10kv.off");
  return mesh;
}

void run_parse(benchmark::State& state, const std::string& bytes,
               const std::function<kr::TriangleMesh(std::string_view)>& parse) {
  for (auto _ : state) benchmark::DoNotOptimize(parse(bytes));
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations() * bytes.size()));
  state.counters["triangles"] = static_cast<double>(dragon().num_triangles());
  state.counters["file_bytes"] = static_cast<double>(bytes.size());
}

void BM_ParseObj(benchmark::State& state) {
  run_parse(state, kr::format_obj(dragon()), [](auto b) { return kr::parse_obj(b, "dragon.obj"); });
}
void BM_ParseOff(benchmark::State& state) {
  run_parse(state, kr::format_off(dragon()), [](auto b) { return kr::parse_off(b, "dragon.off"); });
}
void BM_ParseStlBinary(benchmark::State& state) {
  run_parse(state, kr::format_stl_binary(dragon()),
            [](auto b) { return kr::parse_stl(b, "dragon.stl"); });
}
void BM_ParseStlAscii(benchmark::State& state) {
  run_parse(state, kr::format_stl_ascii(dragon()),
            [](auto b) { return kr::parse_stl(b, "dragon.stl"); });
}
void BM_ParsePlyBinary(benchmark::State& state) {
  run_parse(state, kr::format_ply(dragon()), [](auto b) { return kr::parse_ply(b, "dragon.ply"); });
}
void BM_ParsePlyAscii(benchmark::State& state) {
  run_parse(state, kr::format_ply(dragon(), kr::PlyEncoding::ascii),
            [](auto b) { return kr::parse_ply(b, "dragon.ply"); });
}

void BM_AnalyzeMesh(benchmark::State& state) {
  for (auto _ : state) benchmark::DoNotOptimize(kr::analyze_mesh(dragon()));
  state.counters["triangles"] = static_cast<double>(dragon().num_triangles());
}

BENCHMARK(BM_ParseObj)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ParseOff)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ParseStlBinary)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ParseStlAscii)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ParsePlyBinary)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ParsePlyAscii)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_AnalyzeMesh)->Unit(benchmark::kMillisecond);

}  // namespace
