// A bundled scene file, prepared through the product cache and run for 1000 haptic cycles in
// simulated time, with nothing but the installed Kilohertz::scene (docs/SCENES.md, "Running a
// scene from C++"). Usage: scene_tour [SCENE.json] (default: the bundled alpha puzzle).
#include <khz/reduced/worker_threads.hpp>
#include <khz/scene/cache_directory.hpp>
#include <khz/scene/prepare_scene.hpp>
#include <khz/scene/read_scene.hpp>
#include <khz/scene/scene_runtime.hpp>

#include <iostream>
#include <string>

int main(int argc, char** argv) {
  // The preparation's threads, as the khz tools bound them (KHZ_THREADS; a scene's "threads"
  // overrides it for its preparation).
  khz::reduced::set_worker_threads_from_environment();
  const khz::scene::SceneDescription scene =
      khz::scene::read_scene(argc > 1 ? argv[1] : KHZ_EXAMPLE_SCENE);
  khz::scene::ProductCache cache(khz::scene::default_cache_directory());
  khz::scene::PrepareOptions options;
  options.progress = [last = std::string()](const std::string& object, khz::scene::PrepareStep step,
                                            const khz::reduced::Progress&) mutable {
    const std::string now = object + ' ' + std::string(khz::scene::step_name(step));
    if (now != last) std::cout << "preparing " << (last = now) << '\n';
    return true;  // false cancels
  };
  const khz::scene::PreparedScene prepared = khz::scene::prepare_scene(scene, cache, options);

  khz::scene::SceneRuntime runtime(prepared);  // the scene's own devices, one per hand
  runtime.open_devices();
  const double period = 1.0 / scene.loop.rate_hz;
  for (int i = 0; i < 1000; ++i) {
    const double t = i * period;
    const auto records = runtime.world().cycle(t, t + period, [t] { return t; });
    if (i % 100 == 0) {
      std::cout << "t = " << t << " s, hand 0: contact force " << records[0].contact.force.norm()
                << " N, rendered " << records[0].rendered.force.norm() << " N\n";
    }
  }
  runtime.close_devices();
}
