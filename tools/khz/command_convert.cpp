#include "commands.hpp"

#include <khz/reduced/io/mesh_file.hpp>

#include <iostream>
#include <memory>

namespace khz::tool {

void add_convert_command(CLI::App& app) {
  struct Arguments {
    std::string input, output;
    bool ascii = false;
  };
  auto args = std::make_shared<Arguments>();
  CLI::App* command = app.add_subcommand(
      "convert", "Convert a mesh between formats (chosen by the file extensions)");
  command->add_option("input", args->input, "Mesh to read")->required()->check(CLI::ExistingFile);
  command
      ->add_option("output", args->output,
                   "Mesh to write (.obj .off .stl .ply .vtk .vtu .msh .node)")
      ->required();
  command->add_flag("--ascii", args->ascii, "Write STL and PLY as text instead of binary");
  command->callback([args] {
    if (is_volume_mesh_file(args->input)) {
      reduced::write_volume_mesh(args->output, reduced::read_volume_mesh(args->input));
    } else {
      reduced::write_triangle_mesh(args->output, reduced::read_triangle_mesh(args->input),
                                   {.binary = !args->ascii});
    }
    std::cout << "wrote " << args->output << "\n";
  });
}

}  // namespace khz::tool
