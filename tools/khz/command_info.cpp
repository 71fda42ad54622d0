#include "commands.hpp"

#include <khz/reduced/io/mesh_file.hpp>
#include <khz/reduced/mesh/mesh_report.hpp>

#include <Eigen/Geometry>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <iostream>
#include <memory>
#include <set>

namespace khz::tool {
namespace {

void describe_volume_mesh(const reduced::VolumeMesh& mesh) {
  const char* kind =
      mesh.element_type == reduced::ElementType::tetrahedron ? "tetrahedra" : "hexahedra";
  std::cout << "  vertices:   " << mesh.num_vertices() << "\n"
            << "  elements:   " << mesh.num_elements() << " " << kind << "\n";
  if (mesh.num_vertices() > 0) {
    const Eigen::Vector3d lo = mesh.vertices.colwise().minCoeff();
    const Eigen::Vector3d hi = mesh.vertices.colwise().maxCoeff();
    std::cout << "  bounds:     [" << lo.transpose() << "] .. [" << hi.transpose() << "]\n";
  }
  if (mesh.element_groups.size() > 0) {
    const std::set<int> groups(mesh.element_groups.begin(), mesh.element_groups.end());
    std::cout << "  groups:     " << groups.size() << "\n";
  }
}

}  // namespace

bool is_volume_mesh_file(const std::string& path) {
  std::string extension = std::filesystem::path(path).extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return extension == ".msh" || extension == ".node" || extension == ".ele";
}

void add_info_command(CLI::App& app) {
  auto file = std::make_shared<std::string>();
  CLI::App* command = app.add_subcommand("info", "Describe a mesh file: counts, bounds, topology");
  command->add_option("file", *file, "Mesh file (.obj .off .stl .ply .msh .node .ele)")
      ->required()
      ->check(CLI::ExistingFile);
  command->callback([file] {
    std::cout << *file << "\n";
    if (is_volume_mesh_file(*file)) {
      describe_volume_mesh(reduced::read_volume_mesh(*file));
    } else {
      std::cout << reduced::analyze_mesh(reduced::read_triangle_mesh(*file));
    }
  });
}

}  // namespace khz::tool
