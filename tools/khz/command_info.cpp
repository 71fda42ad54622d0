#include "commands.hpp"
#include "describe_files.hpp"

#include <khz/contact/io/distance_field_file.hpp>
#include <khz/contact/io/point_tree_file.hpp>
#include <khz/contact/io/pointshell_file.hpp>
#include <khz/reduced/errors.hpp>
#include <khz/reduced/io/basis_file.hpp>
#include <khz/reduced/io/mesh_file.hpp>
#include <khz/reduced/io/mesh_fingerprint.hpp>
#include <khz/reduced/io/reduced_model_file.hpp>
#include <khz/reduced/mesh/mesh_report.hpp>

#include <algorithm>
#include <array>
#include <cctype>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <memory>
#include <set>
#include <sstream>
#include <string_view>
#include <vector>

namespace khz::tool {
namespace {

/// The volumetric mesh formats read_volume_mesh() reads.
constexpr std::array<std::string_view, 3> volume_mesh_extensions{".msh", ".node", ".ele"};

void describe_surface_mesh_file(const std::string& file) {
  std::cout << reduced::analyze_mesh(reduced::read_triangle_mesh(file));
}

void describe_volume_mesh_file(const std::string& file) {
  const reduced::VolumeMesh mesh = reduced::read_volume_mesh(file);
  const char* kind =
      mesh.element_type == reduced::ElementType::tetrahedron ? "tetrahedra" : "hexahedra";
  info_line("vertices") << mesh.num_vertices() << "\n";
  info_line("elements") << mesh.num_elements() << " " << kind << "\n";
  info_line("bounds") << box_text(bounding_box(mesh.vertices)) << "\n";
  if (mesh.element_groups.size() > 0) {
    const std::set<int> groups(mesh.element_groups.begin(), mesh.element_groups.end());
    info_line("groups") << groups.size() << "\n";
  }
}

/// The lines basis files and reduced model files share: what the file is, its basis and mesh.
void describe_basis_header(std::string_view description, const reduced::BasisFileInfo& info) {
  info_line("kind") << description << ", format version " << info.format_version << "\n";
  info_line("vertices") << info.num_vertices << " (U has " << 3 * info.num_vertices << " rows)\n";
  info_line("basis size r") << info.size << "\n";
  info_line("fixed vertices") << info.num_fixed_vertices << "\n";
  info_line("fingerprint") << reduced::fingerprint_text(info.fingerprint) << "\n";
  info_line("recipe") << (info.recipe.empty() ? "(none)" : info.recipe) << "\n";
}

void describe_basis_file(const std::string& file) {
  const reduced::BasisFileInfo info = reduced::read_basis_info(file);
  describe_basis_header(reduced::basis_file_format.description, info);
  describe_file_size(info.file_bytes);
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
  info_line("groups") << info.groups.size() << "\n";
  for (std::size_t g = 0; g < info.groups.size(); ++g) {
    info_line("group " + std::to_string(g), 4);
    describe_material(info.groups[g]);
  }
  const reduced::ReducedIntegratorDefaults& defaults = info.defaults;
  info_line("time step") << defaults.newmark.time_step << " s (Newmark beta "
                         << defaults.newmark.beta << ", gamma " << defaults.newmark.gamma << ")\n";
  info_line("damping") << "Rayleigh alpha " << defaults.newmark.mass_damping << " 1/s, beta "
                       << defaults.newmark.stiffness_damping << " s\n";
  info_line("Newton") << "at most " << defaults.max_newton_iterations << " iteration(s), tolerance "
                      << defaults.newton_tolerance << "\n";
  describe_file_size(info.basis.file_bytes);
}

/// One kind of file `khz info` describes.
struct FileKind {
  std::string_view name;                     ///< What the help calls it.
  std::vector<std::string_view> extensions;  ///< Lowercase, with the dot.
  void (*describe)(const std::string& file);
};

/// Every kind of file khz writes or reads, in the order the help lists them.
const std::vector<FileKind>& file_kinds() {
  static const std::vector<FileKind> kinds{
      {"surface mesh", {".obj", ".off", ".stl", ".ply"}, describe_surface_mesh_file},
      {"volume mesh",
       {volume_mesh_extensions.begin(), volume_mesh_extensions.end()},
       describe_volume_mesh_file},
      {"basis", {reduced::basis_file_extension}, describe_basis_file},
      {"reduced model", {reduced::reduced_model_file_extension}, describe_reduced_model_file},
      {"distance field", {contact::distance_field_file_extension}, describe_distance_field_file},
      {"pointshell", {contact::pointshell_file_extension}, describe_pointshell_file},
      {"point tree", {contact::point_tree_file_extension}, describe_point_tree_file},
      {"scene", {".json"}, describe_scene_file},
      {"khz run cycle log or device trajectory", {".csv"}, describe_csv_file},
      {"PNG image", {".png"}, describe_png_file},
      {"ParaView distance field",
       {".vti"},
       [](const std::string& file) {
         describe_unread_file(file,
                              "VTK XML image data for ParaView (a distance field, "
                              "contact::write_distance_field_vti)");
       }},
      {"ParaView mesh",
       {".vtk", ".vtu"},
       [](const std::string& file) {
         describe_unread_file(file, "VTK mesh for ParaView (khz convert, write_*_mesh)");
       }},
      {"ParaView time series",
       {".pvd", ".vtp"},
       [](const std::string& file) {
         describe_unread_file(file,
                              "a khz run frame series for ParaView (.pvd collection of .vtp "
                              "surfaces and points, khz run --paraview)");
       }},
      {"khz report",
       {".md"},
       [](const std::string& file) {
         describe_unread_file(file, "Markdown (khz report writes report.md beside its plots)");
       }},
      {"NumPy or MATLAB basis export",
       {".npy", ".mat"},
       [](const std::string& file) {
         describe_unread_file(file,
                              "basis U for NumPy or MATLAB/Octave (reduced::write_basis_npy, "
                              "write_basis_mat)");
       }},
  };
  return kinds;
}

/// "surface mesh (.obj .off .stl .ply), volume mesh (.msh .node .ele), ..."
std::string supported_kinds_text() {
  std::string text;
  for (const FileKind& kind : file_kinds()) {
    if (!text.empty()) text += ", ";
    text += kind.name;
    for (std::size_t e = 0; e < kind.extensions.size(); ++e) {
      text += e == 0 ? " (" : " ";
      text += kind.extensions[e];
    }
    text += ")";
  }
  return text;
}

std::string lower_extension(const std::string& path) {
  std::string extension = std::filesystem::path(path).extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return extension;
}

/// The kind `file`'s extension names. @throws reduced::Error listing the supported kinds.
const FileKind& kind_of(const std::string& file) {
  const std::string extension = lower_extension(file);
  for (const FileKind& kind : file_kinds()) {
    if (std::ranges::find(kind.extensions, extension) != kind.extensions.end()) return kind;
  }
  throw reduced::Error(
      file + ": khz info does not know " +
      (extension.empty() ? "files without an extension" : "the extension \"" + extension + "\"") +
      "; it describes: " + supported_kinds_text());
}

}  // namespace

std::ostream& info_line(std::string_view label, int indent) {
  constexpr int value_column = 18;
  const std::string text =
      std::string(static_cast<std::size_t>(indent), ' ') + std::string(label) + ":";
  return std::cout << std::left << std::setw(value_column - 1) << text << std::right << " ";
}

void describe_file_size(std::uintmax_t bytes) { info_line("on disk") << bytes << " bytes\n"; }

std::string point_text(const Eigen::Vector3d& point) {
  const Eigen::IOFormat row(Eigen::StreamPrecision, Eigen::DontAlignCols, ", ", ", ", "", "", "(",
                            ")");
  std::ostringstream text;
  text << point.transpose().format(row);
  return text.str();
}

std::string box_text(const Eigen::AlignedBox3d& box) {
  if (box.isEmpty()) return "empty";
  return "min " + point_text(box.min()) + ", max " + point_text(box.max()) + ", size " +
         point_text(box.sizes());
}

Eigen::AlignedBox3d bounding_box(const reduced::VertexMatrix& points) {
  if (points.rows() == 0) return Eigen::AlignedBox3d();
  return {points.colwise().minCoeff().transpose(), points.colwise().maxCoeff().transpose()};
}

bool is_volume_mesh_file(const std::string& path) {
  return std::ranges::find(volume_mesh_extensions, lower_extension(path)) !=
         volume_mesh_extensions.end();
}

void add_info_command(CLI::App& app) {
  auto file = std::make_shared<std::string>();
  CLI::App* command = app.add_subcommand(
      "info",
      "Describe any file khz writes or reads: meshes, bases, reduced models, distance fields, "
      "pointshells, point trees, scenes, trajectories, images and exports");
  command
      ->add_option("file", *file,
                   "The file, its kind chosen by extension: " + supported_kinds_text())
      ->required()
      ->check(CLI::ExistingFile);
  command->callback([file] {
    const FileKind& kind = kind_of(*file);
    std::cout << *file << "\n";
    kind.describe(*file);
  });
}

}  // namespace khz::tool
