#include "commands.hpp"

#include <khz/reduced/io/basis_file.hpp>
#include <khz/reduced/io/mesh_file.hpp>
#include <khz/reduced/io/mesh_fingerprint.hpp>
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

void describe_basis_file(const std::string& file) {
  const reduced::BasisFileInfo info = reduced::read_basis_info(file);
  std::cout << "  kind:           Kilohertz basis file, format version " << info.format_version
            << "\n"
            << "  vertices:       " << info.num_vertices << " (U has " << 3 * info.num_vertices
            << " rows)\n"
            << "  basis size r:   " << info.size << "\n"
            << "  fixed vertices: " << info.num_fixed_vertices << "\n"
            << "  fingerprint:    " << reduced::fingerprint_text(info.fingerprint) << "\n"
            << "  recipe:         " << (info.recipe.empty() ? "(none)" : info.recipe) << "\n"
            << "  on disk:        " << info.file_bytes << " bytes\n";
}

std::string lower_extension(const std::string& path) {
  std::string extension = std::filesystem::path(path).extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return extension;
}

}  // namespace

bool is_volume_mesh_file(const std::string& path) {
  const std::string extension = lower_extension(path);
  return extension == ".msh" || extension == ".node" || extension == ".ele";
}

bool is_basis_file(const std::string& path) {
  return lower_extension(path) == reduced::basis_file_extension;
}

void add_info_command(CLI::App& app) {
  auto file = std::make_shared<std::string>();
  CLI::App* command =
      app.add_subcommand("info", "Describe a mesh file (counts, bounds, topology) or a basis file");
  command
      ->add_option("file", *file,
                   "Mesh file (.obj .off .stl .ply .msh .node .ele) or basis file (.khzbasis)")
      ->required()
      ->check(CLI::ExistingFile);
  command->callback([file] {
    std::cout << *file << "\n";
    if (is_basis_file(*file)) {
      describe_basis_file(*file);
    } else if (is_volume_mesh_file(*file)) {
      describe_volume_mesh(reduced::read_volume_mesh(*file));
    } else {
      std::cout << reduced::analyze_mesh(reduced::read_triangle_mesh(*file));
    }
  });
}

}  // namespace khz::tool
