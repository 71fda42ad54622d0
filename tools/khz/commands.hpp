#pragma once
// The khz tool's subcommands. Each registers its options on the CLI11 app and runs when chosen.

#include <CLI/CLI.hpp>

namespace khz::tool {

/// `khz info FILE`: describes any file khz writes or reads, by extension: meshes (counts,
/// bounds, topology checks), basis and reduced model files (format version, n, r, mesh
/// fingerprint, recipe, materials, integrator defaults), distance fields, pointshells and point
/// trees (grid, levels, points, r, fingerprint), scenes (validated, then objects, products,
/// haptic object, device, loop), trajectories, PNG images, and the ParaView and NumPy/MATLAB
/// exports it has no reader for (size only). Unknown extensions are an error listing the known
/// ones.
void add_info_command(CLI::App& app);
/// `khz convert IN OUT`: converts between mesh formats, chosen by extension.
void add_convert_command(CLI::App& app);
/// `khz repair IN OUT`: welds, drops degenerate triangles and orients a surface mesh.
void add_repair_command(CLI::App& app);
/// `khz prep SCENE [--cache DIR]`: prepares a scene's objects (scene::prepare_scene()) through
/// the product cache, with progress bars on stderr and a table of what was computed or read, in
/// how many seconds, on stdout.
void add_prep_command(CLI::App& app);
/// `khz shape SPEC OUT`: writes a procedural mesh (scene::procedural_shape(), a scene's
/// "shape:SPEC") to a surface mesh file, format by extension.
void add_shape_command(CLI::App& app);
/// `khz run SCENE [--trajectory FILE | --operator SCRIPT | --device NAME]`: prepares the scene
/// and runs its haptic cycle in simulated time (scene::run_scene()), writing cycles.csv and PNG
/// frames to the output directory and printing a summary.
void add_run_command(CLI::App& app);
/// `khz report SCENE [same options as run]`: runs the scene, replays its states in contact
/// under every level of detail and time budget (scene::sweep_contact()) and writes report.md with
/// plots (run::write_report()).
void add_report_command(CLI::App& app);

/// True if `path` names a volumetric mesh format (.msh, .node, .ele) rather than a surface.
bool is_volume_mesh_file(const std::string& path);

}  // namespace khz::tool
