// khz_viewer: a scene run interactively, the mouse as the manipulandum (docs/SCENES.md,
// "Interactive viewer"). The haptic cycle runs on a haptic::HapticLoop thread at the scene's
// loop rate; this thread draws with OpenGL from the snapshots the loop hands over through a
// haptic::TripleBuffer and moves the mouse device from the cursor. Neither thread waits for the
// other.
#include "overlay_view.hpp"
#include "scene_view.hpp"
#include "viewer_window.hpp"

#include <khz/haptic/loop/haptic_loop.hpp>
#include <khz/haptic/loop/triple_buffer.hpp>
#include <khz/reduced/worker_threads.hpp>
#include <khz/render/png_file.hpp>
#include <khz/run/scene_framing.hpp>
#include <khz/scene/cache_directory.hpp>
#include <khz/scene/prepare_scene.hpp>
#include <khz/scene/read_scene.hpp>
#include <khz/scene/scene_runtime.hpp>
#include <khz/viewer/cursor_drag.hpp>
#include <khz/viewer/mouse_device.hpp>
#include <khz/viewer/mouse_placement.hpp>
#include <khz/viewer/overlay_text.hpp>
#include <khz/viewer/preparation_messages.hpp>
#include <khz/viewer/scene_snapshot.hpp>

#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <span>
#include <string>
#include <thread>
#include <vector>

namespace khz::viewer {
namespace {

using Clock = std::chrono::steady_clock;

/// The command line.
struct ViewerRequest {
  std::string scene, cache, screenshot;
  int frames = 0;  ///< Quit after this many drawn frames; 0: when the user quits.
  int width = 1024, height = 768;
};

/// The scene prepared through the product cache (--cache, or scene::default_cache_directory()),
/// one line on stderr per product (PreparationMessages: "cached" or "preparing") and a summary.
scene::PreparedScene prepare(const scene::SceneDescription& description,
                             const ViewerRequest& request) {
  const std::filesystem::path directory = request.cache.empty()
                                              ? scene::default_cache_directory()
                                              : std::filesystem::path(request.cache);
  if (directory.empty()) {
    throw reduced::Error("no cache directory: neither XDG_CACHE_HOME nor HOME is set; use --cache");
  }
  scene::ProductCache cache(directory);
  scene::PrepareOptions options;
  PreparationMessages messages;
  options.progress = [&](const std::string& object, scene::PrepareStep step,
                         const reduced::Progress& progress) {
    const std::string line = messages.line(object, step, progress);
    if (!line.empty()) std::cerr << "khz_viewer: " << line << '\n';
    return true;
  };
  scene::PreparedScene prepared = scene::prepare_scene(description, cache, options);
  std::cerr << "khz_viewer: " << preparation_summary(prepared) << '\n';
  return prepared;
}

/// What the overlay calls each hand: its object, and what moves it.
std::vector<std::string> hand_names(const scene::SceneRuntime& runtime) {
  std::vector<std::string> names;
  for (int h = 0; h < runtime.hand_count(); ++h) {
    names.push_back(
        runtime.description().objects[static_cast<std::size_t>(runtime.held_object(h))].name +
        (h == 0 ? ", mouse" : ", scene's device"));
  }
  return names;
}

/// A mouse has no mechanical limits: its workspace box (m, around the device origin) only
/// bounds what MouseDevice::set_position() accepts. The drag keeps the target within twice the
/// scene's radius of its centre anyway, which this exceeds for any hand-sized scene.
constexpr double mouse_reach = 10.0;
/// At most this many frames per second, so the drawing leaves the haptic thread its CPU.
constexpr double max_frame_rate = 60.0;

double seconds_between(Clock::time_point from, Clock::time_point to) {
  return std::chrono::duration<double>(to - from).count();
}

int view(const ViewerRequest& request) {
  const scene::SceneDescription description = scene::read_scene(request.scene);
  const scene::PreparedScene prepared = prepare(description, request);
  const std::string name = std::filesystem::path(request.scene).stem().string();

  // The mouse replaces the first hand's device (the others keep the scene's), placed by
  // mouse_mapping() once the runtime knows where the held object's grasp point starts.
  MouseDevice mouse(description.loop.rate_hz, mouse_reach);
  std::vector<haptic::Device*> devices(description.haptic.size(), nullptr);
  devices.front() = &mouse;
  scene::SceneRuntime runtime(prepared, devices);
  const haptic::Pose start = runtime.world().coupling(0).simulation_pose();
  const haptic::WorkspaceMapping mapping = mouse_mapping(start);
  runtime.device().set_mapping(mapping);

  const run::SceneFraming framing = run::frame_scene(runtime);
  const SnapshotLayout layout(runtime);
  SceneView scene_view(runtime, layout, framing);
  const Eigen::Vector3d reach = Eigen::Vector3d::Constant(2.0 * framing.radius);
  CursorDrag drag(start.position, {framing.centre - reach, framing.centre + reach},
                  0.05 * framing.radius);
  ViewerWindow window(
      name + " - khz_viewer", request.width, request.height, framing, drag,
      [&](const Eigen::Vector3d& target) { mouse.set_position(device_position(mapping, target)); });
  OverlayView overlay;
  const std::vector<std::string> names = hand_names(runtime);
  const std::vector<std::string> help = overlay_help();

  // The hand-off: the haptic thread fills back() and publishes, this one takes front().
  SceneSnapshot snapshot;
  layout.capture(runtime, snapshot);
  for (int h = 0; h < runtime.hand_count(); ++h) {
    haptic::CycleRecord& at_start = snapshot.records[static_cast<std::size_t>(h)];
    at_start.simulation = at_start.manipulandum = runtime.world().coupling(h).simulation_pose();
  }
  haptic::TripleBuffer<SceneSnapshot> snapshots(snapshot);

  haptic::HapticLoop loop(description.loop);
  runtime.open_devices();
  Clock::time_point origin;  // the loop's time 0, from cycle 0's wake-up
  loop.start([&](const haptic::CycleClock& clock) {
    if (clock.cycle == 0) {
      origin = Clock::now() - std::chrono::duration_cast<Clock::duration>(
                                  std::chrono::duration<double>(clock.time));
    }
    runtime.world().cycle(clock.time, clock.time + clock.period,
                          [&] { return seconds_between(origin, Clock::now()); });
    layout.capture(runtime, snapshots.back());
    snapshots.publish();
  });
  for (const std::string& warning : loop.warnings()) {
    std::cerr << "khz_viewer: " << warning << '\n';
  }

  const auto frame_period = std::chrono::duration_cast<Clock::duration>(
      std::chrono::duration<double>(1.0 / max_frame_rate));
  Clock::time_point next_frame = Clock::now();
  // The overlay's rates, measured over about half a second.
  OverlayRates rates;
  Clock::time_point measured = next_frame;
  std::int64_t measured_cycles = 0;
  int measured_frames = 0;
  for (int frames = 1;; ++frames) {
    // The last frame is drawn once quitting is asked for, so --screenshot saves what was seen.
    const bool last =
        window.closing() || !loop.running() || (request.frames > 0 && frames >= request.frames);
    snapshots.update();
    const SceneSnapshot& shown = snapshots.front();
    const Eigen::Vector2i size = window.framebuffer_size();
    scene_view.draw(shown, window.camera(), size.x(), size.y());
    overlay.draw(
        overlay_status(
            rates, std::span(shown.records).first(static_cast<std::size_t>(layout.hand_count())),
            names),
        help, size.x(), size.y());
    if (last) {
      if (!request.screenshot.empty()) render::write_png(window.read_frame(), request.screenshot);
      break;
    }
    window.show_frame();

    const Clock::time_point now = Clock::now();
    if (seconds_between(measured, now) >= 0.5) {
      const haptic::LoopStatistics statistics = loop.statistics();
      const double seconds = seconds_between(measured, now);
      rates.cycles_per_second = static_cast<double>(statistics.cycles - measured_cycles) / seconds;
      rates.microseconds_per_cycle = statistics.mean_work;
      rates.frames_per_second = (frames - measured_frames) / seconds;
      measured = now;
      measured_cycles = statistics.cycles;
      measured_frames = frames;
    }
    next_frame = std::max(next_frame + frame_period, now);
    std::this_thread::sleep_until(next_frame);
  }
  loop.stop();
  runtime.close_devices();
  if (!loop.error().empty()) throw reduced::Error("the haptic loop stopped: " + loop.error());
  const haptic::LoopStatistics statistics = loop.statistics();
  std::printf("%s: %lld cycles at %g Hz, work %.1f µs mean, %.1f µs p99, %lld deadline misses\n",
              name.c_str(), static_cast<long long>(statistics.cycles), description.loop.rate_hz,
              statistics.mean_work, statistics.p99_work,
              static_cast<long long>(statistics.deadline_misses));
  return 0;
}

}  // namespace
}  // namespace khz::viewer

int main(int argc, char** argv) {
  CLI::App app(
      "khz_viewer: run a scene interactively, the mouse as the manipulandum (left drag: move "
      "in the plane facing you; wheel: move along the view; right drag: orbit the camera; "
      "Shift+wheel or +/-: zoom; R: reset the view; Esc: quit)",
      "khz_viewer");
  khz::viewer::ViewerRequest request;
  app.add_option("scene", request.scene, "Scene file (docs/SCENES.md)")
      ->required()
      ->check(CLI::ExistingFile);
  app.add_option("--cache", request.cache,
                 "Product cache directory (default: $XDG_CACHE_HOME/kilohertz or "
                 "~/.cache/kilohertz, as khz prep)");
  app.add_option("--frames", request.frames, "Quit after this many frames (0: never)")
      ->check(CLI::NonNegativeNumber);
  app.add_option("--screenshot", request.screenshot, "Save the last frame as this PNG file");
  app.add_option("--width", request.width, "Window width (screen coordinates)")
      ->check(CLI::Range(16, 16384));
  app.add_option("--height", request.height, "Window height (screen coordinates)")
      ->check(CLI::Range(16, 16384));
  try {
    khz::reduced::set_worker_threads_from_environment();  // KHZ_THREADS
    app.parse(argc, argv);
    return khz::viewer::view(request);
  } catch (const CLI::ParseError& error) {
    return app.exit(error);
  } catch (const khz::reduced::Error& error) {
    std::cerr << "khz_viewer: " << error.what() << "\n";
    return 1;
  }
}
