#pragma once
// Reading and writing mesh files, with the format chosen from the file name.

#include <khz/reduced/export.hpp>
#include <khz/reduced/io/ply.hpp>
#include <khz/reduced/io/vtk.hpp>
#include <khz/reduced/mesh/triangle_mesh.hpp>
#include <khz/reduced/mesh/volume_mesh.hpp>

#include <filesystem>

namespace khz::reduced {

/// Reads a surface mesh; the extension (case-insensitive) picks the format: .obj, .off, .stl,
/// .ply. The result passes validate().
/// @throws IoError if the file cannot be read; ParseError (file and line or byte) if it is
///         malformed; Error for an unknown extension, listing the supported ones.
KHZ_REDUCED_API TriangleMesh read_triangle_mesh(const std::filesystem::path& file);

/// Options for write_triangle_mesh().
struct TriangleMeshWriteOptions {
  bool binary = true;  ///< STL and PLY: binary (little-endian) rather than ASCII.
};

/// Writes a surface mesh; the extension picks the format: .obj, .off, .stl, .ply, .vtk, .vtu.
/// @throws MeshError if the mesh fails validate(); IoError if the file cannot be written;
///         Error for an unknown extension.
KHZ_REDUCED_API void write_triangle_mesh(const std::filesystem::path& file,
                                         const TriangleMesh& mesh,
                                         const TriangleMeshWriteOptions& options = {});

/// Reads a volumetric mesh: .msh (Gmsh MSH 2.2 ASCII, 4.1 ASCII or binary), or TetGen given
/// either the .node or the .ele path (the other file is found beside it). The result passes
/// validate().
/// @throws IoError, ParseError or Error as read_triangle_mesh().
KHZ_REDUCED_API VolumeMesh read_volume_mesh(const std::filesystem::path& file);

/// Writes a volumetric mesh: .msh (MSH 2.2 ASCII; format_gmsh() writes MSH 4.1), .node (also
/// writes the .ele beside it), .vtk or .vtu.
/// `fields` are used by .vtk/.vtu only.
/// @throws MeshError, IoError or Error as write_triangle_mesh().
KHZ_REDUCED_API void write_volume_mesh(const std::filesystem::path& file, const VolumeMesh& mesh,
                                       const VtkFields& fields = {});

}  // namespace khz::reduced
