#include "commands.hpp"

#include <khz/reduced/io/basis_file.hpp>
#include <khz/reduced/io/mesh_file.hpp>
#include <khz/reduced/io/mesh_fingerprint.hpp>
#include <khz/reduced/io/reduced_model_file.hpp>
#include <khz/reduced/mesh/mesh_report.hpp>

#include <Eigen/Geometry>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <iostream>
#include <memory>
#include <set>
#include <string_view>

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

/// The lines basis files and reduced model files share: what the file is, its basis and mesh.
void describe_basis_header(std::string_view description, const reduced::BasisFileInfo& info) {
  std::cout << "  kind:           " << description << ", format version " << info.format_version
            << "\n"
            << "  vertices:       " << info.num_vertices << " (U has " << 3 * info.num_vertices
            << " rows)\n"
            << "  basis size r:   " << info.size << "\n"
            << "  fixed vertices: " << info.num_fixed_vertices << "\n"
            << "  fingerprint:    " << reduced::fingerprint_text(info.fingerprint) << "\n"
            << "  recipe:         " << (info.recipe.empty() ? "(none)" : info.recipe) << "\n";
}

void describe_file_size(const reduced::BasisFileInfo& info) {
  std::cout << "  on disk:        " << info.file_bytes << " bytes\n";
}

void describe_basis_file(const std::string& file) {
  const reduced::BasisFileInfo info = reduced::read_basis_info(file);
  describe_basis_header(reduced::basis_file_format.description, info);
  describe_file_size(info);
}

void describe_material(const reduced::ReducedModelGroupInfo& group) {
  const reduced::Material& material = group.material;
  if (material.is_stvk()) {
    std::cout << "StVK, lambda = " << material.lame().lambda << " Pa, mu = " << material.lame().mu
              << " Pa";
  } else {
    std::cout << "general, C = " << group.elasticity_scale
              << " x C0 (max |C_ij| = " << material.elasticity().cwiseAbs().maxCoeff() << " Pa)";
  }
  std::cout << ", density " << material.density() << " kg/m^3\n";
}

void describe_reduced_model_file(const std::string& file) {
  const reduced::ReducedModelFileInfo info = reduced::read_reduced_model_info(file);
  describe_basis_header(reduced::reduced_model_file_format.description, info.basis);
  std::cout << "  groups:         " << info.groups.size() << "\n";
  for (std::size_t g = 0; g < info.groups.size(); ++g) {
    std::cout << "    group " << g << ":      ";
    describe_material(info.groups[g]);
  }
  const reduced::ReducedIntegratorDefaults& defaults = info.defaults;
  std::cout << "  time step:      " << defaults.newmark.time_step << " s (Newmark beta "
            << defaults.newmark.beta << ", gamma " << defaults.newmark.gamma << ")\n"
            << "  damping:        Rayleigh alpha " << defaults.newmark.mass_damping << " 1/s, beta "
            << defaults.newmark.stiffness_damping << " s\n"
            << "  Newton:         at most " << defaults.max_newton_iterations
            << " iteration(s), tolerance " << defaults.newton_tolerance << "\n";
  describe_file_size(info.basis);
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

bool is_reduced_model_file(const std::string& path) {
  return lower_extension(path) == reduced::reduced_model_file_extension;
}

void add_info_command(CLI::App& app) {
  auto file = std::make_shared<std::string>();
  CLI::App* command =
      app.add_subcommand("info",
                         "Describe a mesh file (counts, bounds, topology), a basis file or a "
                         "reduced model file");
  command
      ->add_option("file", *file,
                   "Mesh file (.obj .off .stl .ply .msh .node .ele), basis file (.khzbasis) or "
                   "reduced model file (.khzmodel)")
      ->required()
      ->check(CLI::ExistingFile);
  command->callback([file] {
    std::cout << *file << "\n";
    if (is_basis_file(*file)) {
      describe_basis_file(*file);
    } else if (is_reduced_model_file(*file)) {
      describe_reduced_model_file(*file);
    } else if (is_volume_mesh_file(*file)) {
      describe_volume_mesh(reduced::read_volume_mesh(*file));
    } else {
      std::cout << reduced::analyze_mesh(reduced::read_triangle_mesh(*file));
    }
  });
}

}  // namespace khz::tool
