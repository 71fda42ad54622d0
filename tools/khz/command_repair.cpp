#include "commands.hpp"

#include <khz/reduced/io/mesh_file.hpp>
#include <khz/reduced/mesh/mesh_repair.hpp>
#include <khz/reduced/mesh/mesh_report.hpp>

#include <iostream>
#include <memory>

namespace khz::tool {

void add_repair_command(CLI::App& app) {
  struct Arguments {
    std::string input, output;
    reduced::RepairOptions options;
    bool keep_orientation = false;
  };
  auto args = std::make_shared<Arguments>();
  CLI::App* command = app.add_subcommand(
      "repair",
      "Weld vertices, drop degenerate triangles, orient and optionally close a surface mesh");
  command->add_option("input", args->input, "Surface mesh to read")
      ->required()
      ->check(CLI::ExistingFile);
  command->add_option("output", args->output, "Surface mesh to write")->required();
  command
      ->add_option("--weld", args->options.weld_tolerance,
                   "Merge vertices closer than this distance (mesh units)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  command->add_flag("--keep-orientation", args->keep_orientation, "Do not reorient triangles");
  command->add_flag("--fill-holes", args->options.fill_holes,
                    "Close every hole with triangles over its boundary (after orienting)");
  command->callback([args] {
    args->options.orient = !args->keep_orientation;
    reduced::TriangleMesh mesh = reduced::read_triangle_mesh(args->input);
    const reduced::RepairSummary summary = reduced::repair_mesh(mesh, args->options);
    reduced::write_triangle_mesh(args->output, mesh);
    std::cout << "welded " << summary.vertices_welded << " vertices, removed "
              << summary.triangles_removed << " triangles"
              << (args->options.orient ? (summary.oriented ? ", oriented" : ", NOT orientable")
                                       : "")
              << "\n";
    if (summary.vertices_split > 0) {
      std::cout << "orienting copied " << summary.vertices_split
                << " vertices at non-manifold points (they keep their positions, so the output "
                   "has duplicate positions; --keep-orientation keeps the mesh welded)\n";
    }
    if (args->options.fill_holes) {
      std::cout << "filled " << summary.holes.filled << " holes";
      if (summary.holes.left_open > 0) {
        std::cout << ", left " << summary.holes.left_open
                  << " open (filling them would make non-manifold edges)";
      }
      std::cout << "\n";
    }
    std::cout << "wrote " << args->output << "\n" << reduced::analyze_mesh(mesh);
  });
}

}  // namespace khz::tool
