// The first preparation of a scene, as a user trying a new mesh meets it (issue 23, item 2):
// every product of the README demo scene (examples/scenes/dragon_on_dino.json: the dino's 256³
// field, the dragon's reduced model, field and 262k-point pointshell) computed into an empty
// cache and the dragon's point tree built, each step's seconds and the total printed as counters.
// The cache is a fresh temporary directory, removed afterwards.
#include <khz/scene/prepare_scene.hpp>
#include <khz/scene/prepared_scene.hpp>
#include <khz/scene/product_cache.hpp>
#include <khz/scene/read_scene.hpp>

#include <benchmark/benchmark.h>
#include <unistd.h>

#include <filesystem>
#include <string>

namespace {

namespace ks = khz::scene;

void BM_FirstPreparationOfTheDemoScene(benchmark::State& state) {
  const ks::SceneDescription scene =
      ks::read_scene(std::filesystem::path(KHZ_SCENE_EXAMPLES_DIR) / "dragon_on_dino.json");
  const std::filesystem::path directory =
      std::filesystem::temp_directory_path() /
      ("khz-bench-scene-preparation-" + std::to_string(::getpid()));
  for (auto _ : state) {
    std::filesystem::remove_all(directory);
    ks::ProductCache cache(directory);
    const ks::PreparedScene prepared = ks::prepare_scene(scene, cache);
    for (const ks::PrepareRecord& record : prepared.records) {
      state.counters[record.object + "_" + std::string(ks::step_name(record.step)) + "_s"] =
          record.seconds;
    }
    state.counters["total_s"] = prepared.total_seconds();
  }
  std::filesystem::remove_all(directory);
}
BENCHMARK(BM_FirstPreparationOfTheDemoScene)
    ->Unit(benchmark::kSecond)
    ->Iterations(1)
    ->UseRealTime();

}  // namespace
