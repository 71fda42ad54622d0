#include "commands.hpp"
#include "scene_session.hpp"

#include <memory>

namespace khz::tool {

void add_run_command(CLI::App& app) {
  auto request = std::make_shared<RunRequest>();
  CLI::App* command = app.add_subcommand(
      "run",
      "Prepare a scene (through the cache) and run its haptic loop in simulated time: writes a "
      "per-cycle CSV (time, force, torque, nodes, contacts, level, microseconds, poses) and PNG "
      "frames");
  add_run_options(*command, *request);
  command->callback([request] { SceneSession(*request).run(false); });
}

}  // namespace khz::tool
