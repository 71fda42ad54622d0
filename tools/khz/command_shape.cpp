#include "commands.hpp"

#include <khz/reduced/io/mesh_file.hpp>
#include <khz/scene/procedural_shape.hpp>

#include <iostream>
#include <memory>

namespace khz::tool {

void add_shape_command(CLI::App& app) {
  struct Arguments {
    std::string spec, output;
    bool ascii = false;
  };
  auto args = std::make_shared<Arguments>();
  std::string shapes;
  for (const std::string_view name : scene::procedural_shape_names()) {
    shapes += (shapes.empty() ? "" : ", ") + std::string(name);
  }
  CLI::App* command = app.add_subcommand(
      "shape", "Write a procedural mesh (a scene's \"shape:SPEC\") to a surface mesh file");
  command
      ->add_option(
          "spec", args->spec,
          "NAME or NAME:KEY=VALUE,... (shapes: " + shapes + "), e.g. peg:side=0.02,length=0.08")
      ->required();
  command->add_option("output", args->output, "Mesh to write (.obj .off .stl .ply .vtk .vtu)")
      ->required();
  command->add_flag("--ascii", args->ascii, "Write STL and PLY as text instead of binary");
  command->callback([args] {
    const reduced::TriangleMesh mesh = scene::procedural_shape(args->spec);
    reduced::write_triangle_mesh(args->output, mesh, {.binary = !args->ascii});
    std::cout << "wrote " << args->output << ": " << scene::canonical_shape_spec(args->spec) << ", "
              << mesh.num_vertices() << " vertices, " << mesh.num_triangles() << " triangles\n";
  });
}

}  // namespace khz::tool
