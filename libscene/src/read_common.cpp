#include "read_common.hpp"

#include <Eigen/Geometry>

#include <numbers>
#include <system_error>

namespace khz::scene::detail {

Eigen::Quaterniond read_rotation(const Json& value, const Location& at) {
  const ObjectReader rotation(value, at, {"axis", "degrees"}, {{"angle", "degrees"}});
  const Eigen::Vector3d axis = rotation.required_vector3("axis", "the rotation axis [x, y, z]");
  if (!(axis.norm() > 0.0)) {
    rotation.at("axis").expected("a non-zero axis", rotation.value("axis"));
  }
  const double degrees = rotation.required_number("degrees", any_value(), "the angle in degrees");
  return Eigen::Quaterniond(
      Eigen::AngleAxisd(degrees * std::numbers::pi / 180.0, axis.normalized()));
}

haptic::Pose read_pose(const Json& value, const Location& at) {
  const ObjectReader pose(value, at, {"position", "rotation"},
                          {{"translation", "position"}, {"orientation", "rotation"}});
  haptic::Pose result;
  result.position = pose.vector3("position", Eigen::Vector3d::Zero());
  if (pose.has("rotation"))
    result.orientation = read_rotation(pose.value("rotation"), pose.at("rotation"));
  return result;
}

std::filesystem::path resolve_file(const std::string& written, const Location& at,
                                   const ReadContext& context, std::string_view what,
                                   bool allow_cgal) {
  namespace fs = std::filesystem;
  constexpr std::string_view cgal_prefix = "cgal:";
  fs::path path;
  std::string origin;
  if (allow_cgal && written.starts_with(cgal_prefix)) {
    const std::string name = written.substr(cgal_prefix.size());
    if (name.empty() || name == "." || name == ".." ||
        name.find_first_of("/\\") != std::string::npos) {
      at.fail(
          "expected \"cgal:NAME\" with NAME one of CGAL's demo meshes, e.g. \"cgal:dino.off\", "
          "got " +
          in_quotes(written));
    }
    if (context.cgal_mesh_dir.empty()) {
      at.fail(
          "the directory of CGAL's demo meshes is unknown: set KHZ_CGAL_MESH_DIR to it (it "
          "holds dino.off; Debian's libcgal-demo ships them in "
          "/usr/share/doc/libcgal-dev/data.tar.gz, under data/meshes)");
    }
    path = (fs::absolute(context.cgal_mesh_dir) / name).lexically_normal();
    origin = "CGAL's demo mesh " + in_quotes(name) + " in " + context.cgal_mesh_dir.string();
  } else {
    const fs::path given(written);
    path = (given.is_absolute() ? given : context.base_directory / given).lexically_normal();
    origin = given.is_absolute()
                 ? "as written"
                 : "from " + in_quotes(written) + " relative to " + context.base_directory.string();
  }
  if (context.check_files) {
    std::error_code error;
    const fs::file_status status = fs::status(path, error);
    if (!fs::exists(status)) {
      at.fail(std::string(what) + " not found: " + path.string() + " (" + origin + ")");
    }
    if (!fs::is_regular_file(status)) {
      at.fail(std::string(what) + " is not a regular file: " + path.string() + " (" + origin + ")");
    }
  }
  return path;
}

}  // namespace khz::scene::detail
