#pragma once
// The khz tool's subcommands. Each registers its options on the CLI11 app and runs when chosen.

#include <CLI/CLI.hpp>

namespace khz::tool {

/// `khz info FILE`: describes a mesh file (counts, bounds, topology checks), a basis file
/// (format version, n, r, mesh fingerprint, recipe, size) or a reduced model file (the same, plus
/// the material groups and integrator defaults).
void add_info_command(CLI::App& app);
/// `khz convert IN OUT`: converts between mesh formats, chosen by extension.
void add_convert_command(CLI::App& app);
/// `khz repair IN OUT`: welds, drops degenerate triangles and orients a surface mesh.
void add_repair_command(CLI::App& app);
/// `khz prep SCENE [--cache DIR]`: prepares a scene's objects (scene::prepare_scene()) through
/// the product cache, with progress bars on stderr and a table of what was computed or read, in
/// how many seconds, on stdout.
void add_prep_command(CLI::App& app);

/// True if `path` names a volumetric mesh format (.msh, .node, .ele) rather than a surface.
bool is_volume_mesh_file(const std::string& path);
/// True if `path` has the basis file extension (.khzbasis).
bool is_basis_file(const std::string& path);
/// True if `path` has the reduced model file extension (.khzmodel).
bool is_reduced_model_file(const std::string& path);

}  // namespace khz::tool
