#pragma once
// What the parts of the scene reader share: the reading context, poses and file paths.

#include "json_reader.hpp"

#include <khz/haptic/common.hpp>

#include <filesystem>
#include <string>
#include <string_view>

namespace khz::scene::detail {

/// What every part of a scene is read with.
struct ReadContext {
  std::string source;                    ///< The scene's name in messages.
  std::filesystem::path base_directory;  ///< Absolute: relative paths resolve against it.
  std::filesystem::path cgal_mesh_dir;   ///< "cgal:NAME" meshes; empty when unknown.
  bool check_files = true;               ///< Require named files to exist.
  double rate_hz = 1000.0;               ///< loop.rate_hz, for defaults derived from it.
};

/// {"axis": [x, y, z], "degrees": angle} as a unit quaternion.
Eigen::Quaterniond read_rotation(const Json& value, const Location& at);
/// {"position": [x, y, z], "rotation": {...}}, both optional (zero, identity).
haptic::Pose read_pose(const Json& value, const Location& at);

/// The path a scene names at `at`: absolute, lexically normal, and (with check_files) an
/// existing regular file. With `allow_cgal`, "cgal:NAME" is CGAL's demo mesh NAME.
/// @param what the file's kind in messages ("mesh file").
std::filesystem::path resolve_file(const std::string& written, const Location& at,
                                   const ReadContext& context, std::string_view what,
                                   bool allow_cgal);

}  // namespace khz::scene::detail
