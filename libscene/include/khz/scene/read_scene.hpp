#pragma once
// Reading and validating scene files (JSON): see docs/SCENES.md for the format.

#include <khz/scene/export.hpp>
#include <khz/scene/scene_description.hpp>

#include <filesystem>
#include <string>
#include <string_view>

namespace khz::scene {

/// How read_scene() and parse_scene() resolve and check the files a scene names.
struct SceneReadOptions {
  /// Directory relative paths (meshes, trajectories, load files) resolve against. Empty: the
  /// scene file's directory (read_scene()) or the current directory (parse_scene()).
  std::filesystem::path base_directory;
  /// Where "cgal:NAME" meshes are. Empty: default_cgal_mesh_dir().
  std::filesystem::path cgal_mesh_dir;
  /// Check that every named file exists (meshes, trajectory, load files). Off only to check a
  /// scene's structure without its data.
  bool check_files = true;
};

/// CGAL's demo meshes ("cgal:NAME"): the environment variable KHZ_CGAL_MESH_DIR if set and not
/// empty; otherwise the directory this build extracted them to (build/<preset>/cgal-data/data/
/// meshes, from Debian's libcgal-demo archive /usr/share/doc/libcgal-dev/data.tar.gz, when the
/// build has tests, benchmarks or examples); otherwise empty (unknown).
KHZ_SCENE_API std::filesystem::path default_cgal_mesh_dir();

/// Reads and validates a scene file. Relative paths resolve against the file's directory
/// unless options.base_directory says otherwise; errors name the file as `file` names it.
/// @throws reduced::IoError if the file cannot be read; SceneError (see parse_scene()).
KHZ_SCENE_API SceneDescription read_scene(const std::filesystem::path& file,
                                          const SceneReadOptions& options = {});

/// Reads a device description on its own: a JSON object with the keys of a scene's "device"
/// (docs/SCENES.md), e.g. {"type": "operator", "keyframes": [...]} — an operator script — or
/// {"type": "trajectory", "file": "path.csv"}. `khz run --operator SCRIPT` reads it. Relative
/// paths resolve against the file's directory; `rate_hz` is the loop rate the device's
/// nominal_rate defaults to.
/// @throws reduced::IoError if the file cannot be read; SceneError at the first problem, with
///         key paths relative to the file's root object.
KHZ_SCENE_API DeviceDescription read_device_file(const std::filesystem::path& file, double rate_hz,
                                                 const SceneReadOptions& options = {});

/// Parses and validates scene text. `source` names it in error messages.
/// @throws SceneError at the first problem, naming the key path and what was expected and
///         found: JSON syntax (line and column), duplicate, unknown (with the closest known key
///         when one is near) or missing keys, wrong types, numbers out of range, values that
///         apply to another method or type than the one chosen, duplicate object names, a
///         haptic object that names no object or lacks the role it should play, an object
///         with no role or that touches nothing, reduced-model settings on a rigid object,
///         and (with check_files) files that do not exist, naming the resolved path.
KHZ_SCENE_API SceneDescription parse_scene(std::string_view text, const std::string& source,
                                           const SceneReadOptions& options = {});

/// Parses and validates a device description given as text (what read_device_file() reads
/// from a file); `source` names it in messages and relative paths resolve against
/// options.base_directory, else the current directory.
/// @throws SceneError as read_device_file().
KHZ_SCENE_API DeviceDescription parse_device(std::string_view text, const std::string& source,
                                             double rate_hz, const SceneReadOptions& options = {});

}  // namespace khz::scene
