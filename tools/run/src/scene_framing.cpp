#include <khz/run/scene_framing.hpp>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>

namespace khz::run {

render::Camera SceneFraming::camera(const Eigen::Vector3d& view_direction,
                                    const Eigen::Vector3d& view_up, int width, int height) const {
  const double fov = std::min(scene_vertical_fov, scene_vertical_fov * width / height);
  const double distance = 1.05 * radius / std::sin(0.5 * fov);
  const Eigen::Vector3d eye = centre + distance * view_direction.normalized();
  return render::Camera(eye, centre, view_up, scene_vertical_fov, width, height);
}

Eigen::Vector3d SceneFraming::turned(const Eigen::Vector3d& direction) const {
  return Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitY(), up) * direction;
}

SceneFraming frame_scene(const scene::SceneRuntime& runtime) {
  Eigen::AlignedBox3d box;
  for (int i = 0; i < static_cast<int>(runtime.description().objects.size()); ++i) {
    const reduced::TriangleMesh& surface = runtime.surface(i);
    for (Eigen::Index v = 0; v < surface.vertices.rows(); ++v) {
      box.extend(runtime.pose(i) * Eigen::Vector3d(surface.vertices.row(v)));
    }
  }
  SceneFraming framing;
  framing.centre = box.center();
  framing.radius = std::max(0.5 * box.diagonal().norm(), 1e-6);
  const scene::SceneDescription& scene = runtime.description();
  if (scene.has_free_objects() && scene.dynamics.gravity.norm() > 0.0) {
    framing.up = -scene.dynamics.gravity.normalized();
  }
  return framing;
}

}  // namespace khz::run
