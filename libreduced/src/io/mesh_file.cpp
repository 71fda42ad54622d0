#include <khz/reduced/errors.hpp>
#include <khz/reduced/io/gmsh.hpp>
#include <khz/reduced/io/mesh_file.hpp>
#include <khz/reduced/io/obj.hpp>
#include <khz/reduced/io/off.hpp>
#include <khz/reduced/io/ply.hpp>
#include <khz/reduced/io/stl.hpp>
#include <khz/reduced/io/tetgen.hpp>
#include <khz/reduced/io/vtk.hpp>

#include "detail/file_bytes.hpp"

#include <algorithm>
#include <cctype>
#include <string>

namespace khz::reduced {
namespace {

std::string lower_extension(const std::filesystem::path& file) {
  std::string extension = file.extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return extension;
}

[[noreturn]] void unknown_extension(const std::filesystem::path& file, const char* supported) {
  throw Error(file.string() + ": unknown mesh file extension '" + file.extension().string() +
              "'; supported: " + supported);
}

}  // namespace

TriangleMesh read_triangle_mesh(const std::filesystem::path& file) {
  const std::string extension = lower_extension(file);
  const std::string source = file.string();
  TriangleMesh mesh;
  if (extension == ".obj") {
    mesh = parse_obj(detail::read_file_bytes(file), source);
  } else if (extension == ".off") {
    mesh = parse_off(detail::read_file_bytes(file), source);
  } else if (extension == ".stl") {
    mesh = parse_stl(detail::read_file_bytes(file), source);
  } else if (extension == ".ply") {
    mesh = parse_ply(detail::read_file_bytes(file), source);
  } else {
    unknown_extension(file, ".obj .off .stl .ply");
  }
  validate(mesh);
  return mesh;
}

void write_triangle_mesh(const std::filesystem::path& file, const TriangleMesh& mesh,
                         const TriangleMeshWriteOptions& options) {
  validate(mesh);
  const std::string extension = lower_extension(file);
  if (extension == ".obj") {
    detail::write_file_bytes(file, format_obj(mesh));
  } else if (extension == ".off") {
    detail::write_file_bytes(file, format_off(mesh));
  } else if (extension == ".stl") {
    detail::write_file_bytes(file,
                             options.binary ? format_stl_binary(mesh) : format_stl_ascii(mesh));
  } else if (extension == ".ply") {
    detail::write_file_bytes(
        file,
        format_ply(mesh, options.binary ? PlyEncoding::binary_little_endian : PlyEncoding::ascii));
  } else if (extension == ".vtk") {
    detail::write_file_bytes(file, format_vtk_legacy(mesh));
  } else if (extension == ".vtu") {
    detail::write_file_bytes(file, format_vtu(mesh));
  } else {
    unknown_extension(file, ".obj .off .stl .ply .vtk .vtu");
  }
}

VolumeMesh read_volume_mesh(const std::filesystem::path& file) {
  const std::string extension = lower_extension(file);
  VolumeMesh mesh;
  if (extension == ".msh") {
    mesh = parse_gmsh(detail::read_file_bytes(file), file.string());
  } else if (extension == ".node" || extension == ".ele") {
    std::filesystem::path node = file;
    std::filesystem::path ele = file;
    node.replace_extension(".node");
    ele.replace_extension(".ele");
    mesh = parse_tetgen(detail::read_file_bytes(node), node.string(), detail::read_file_bytes(ele),
                        ele.string());
  } else {
    unknown_extension(file, ".msh .node .ele");
  }
  validate(mesh);
  return mesh;
}

void write_volume_mesh(const std::filesystem::path& file, const VolumeMesh& mesh,
                       const VtkFields& fields) {
  validate(mesh);
  const std::string extension = lower_extension(file);
  if (extension == ".msh") {
    detail::write_file_bytes(file, format_gmsh(mesh));
  } else if (extension == ".node") {
    const TetgenFiles files = format_tetgen(mesh);
    std::filesystem::path ele = file;
    ele.replace_extension(".ele");
    detail::write_file_bytes(file, files.node);
    detail::write_file_bytes(ele, files.ele);
  } else if (extension == ".vtk") {
    detail::write_file_bytes(file, format_vtk_legacy(mesh, fields));
  } else if (extension == ".vtu") {
    detail::write_file_bytes(file, format_vtu(mesh, fields));
  } else {
    unknown_extension(file, ".msh .node .vtk .vtu");
  }
}

}  // namespace khz::reduced
