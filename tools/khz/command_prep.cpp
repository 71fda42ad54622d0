#include "commands.hpp"
#include "job_processes.hpp"
#include "scene_preparation.hpp"

#include <khz/scene/read_scene.hpp>

#include <iostream>
#include <memory>
#include <string>

namespace khz::tool {

void add_prep_command(CLI::App& app) {
  struct Arguments {
    std::string scene, cache;
  };
  auto args = std::make_shared<Arguments>();
  CLI::App* command = app.add_subcommand(
      "prep",
      "Prepare a scene: compute, or read from the cache, each object's distance field, "
      "pointshell and reduced model, as its roles and model need, and build its point tree");
  command->add_option("scene", args->scene, "Scene file (JSON, docs/SCENES.md)")
      ->required()
      ->check(CLI::ExistingFile);
  command->add_option("--cache", args->cache,
                      "Product cache directory (default: $XDG_CACHE_HOME/kilohertz, else "
                      "~/.cache/kilohertz)");
  command->callback([args] {
    JobProcesses job("prep");  // mpirun -np N khz prep: the N processes share the products
    prepare_with_progress(scene::read_scene(args->scene), cache_directory(args->cache, args->scene),
                          std::cout, job.group());
  });
}

}  // namespace khz::tool
