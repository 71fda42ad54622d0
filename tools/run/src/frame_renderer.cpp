#include <khz/render/rasterizer.hpp>
#include <khz/run/frame_renderer.hpp>
#include <khz/run/scene_framing.hpp>

#include <cmath>
#include <vector>

namespace khz::run {
namespace {

render::Camera frame_camera(const scene::SceneRuntime& runtime, const FrameOptions& options,
                            double& radius) {
  if (options.width < 16 || options.height < 16) {
    throw reduced::Error("FrameOptions: width and height must be at least 16 pixels");
  }
  const SceneFraming framing = frame_scene(runtime);
  radius = framing.radius;
  return framing.camera(framing.turned(options.view_direction), framing.turned(options.up),
                        options.width, options.height);
}

}  // namespace

bool shade_smoothly(const reduced::TriangleMatrix& triangles) noexcept {
  return triangles.rows() > 200;
}

render::Color surface_color(const FrameOptions& options, const scene::SceneRuntime& runtime,
                            int object) {
  for (int h = 0; h < runtime.hand_count(); ++h) {
    if (runtime.held_object(h) == object) return options.held_color;
  }
  return runtime.description().objects[static_cast<std::size_t>(object)].is_dynamic()
             ? options.free_color
             : options.other_color;
}

double arrow_reference_force(const scene::SceneDescription& scene, double arrow_force) {
  const double saturation = scene.coupling.saturation_force;
  return arrow_force > 0.0                               ? arrow_force
         : std::isfinite(saturation) && saturation > 0.0 ? saturation
                                                         : 1.0;
}

FrameRenderer::FrameRenderer(const scene::SceneRuntime& runtime, const FrameOptions& options)
    : m_options(options), m_camera(frame_camera(runtime, options, m_scene_radius)) {
  for (int i = 0; i < static_cast<int>(runtime.description().objects.size()); ++i) {
    m_triangles.push_back(runtime.surface(i).triangles);
    m_colors.push_back(surface_color(options, runtime, i));
  }
  m_reference_force = arrow_reference_force(runtime.description(), options.arrow_force);
}

render::Image FrameRenderer::render(const FrameContent& frame, FrameSummary* summary) const {
  render::Rasterizer rasterizer(m_camera);
  for (std::size_t i = 0; i < frame.surfaces.size(); ++i) {
    render::MeshStyle style;
    style.color = m_colors[i];
    style.smooth = shade_smoothly(m_triangles[i]);
    rasterizer.draw_mesh(frame.surfaces[i], m_triangles[i], style);
  }

  FrameSummary counts;
  for (const PointPicture& picture : frame.points) {
    // Points looked at are depth-tested; points in contact lie inside the other object, so
    // they are drawn over it.
    for (const PointState state :
         {PointState::traversed, PointState::in_contact, PointState::sliding}) {
      reduced::VertexMatrix shown(picture.positions.rows(), 3);
      Eigen::Index count = 0;
      for (std::size_t s = 0; s < picture.states.size(); ++s) {
        if (picture.states[s] == state) {
          shown.row(count++) = picture.positions.row(static_cast<Eigen::Index>(s));
        }
      }
      shown.conservativeResize(count, 3);
      const bool touching = state != PointState::traversed;
      (touching ? counts.in_contact : counts.traversed) += count;
      if (state == PointState::sliding) counts.sliding += count;
      const render::Color color = state == PointState::sliding ? m_options.sliding_color
                                  : touching                   ? m_options.contact_color
                                                               : m_options.traversed_color;
      render::PointStyle style;
      style.radius = 2.0;
      style.always_on_top = touching;
      rasterizer.draw_points(shown, std::span(&color, 1), style);
    }
  }

  for (std::size_t h = 0; h < frame.forces.size(); ++h) {
    const Eigen::Vector3d& grasp = frame.grasp_points[h];
    const Eigen::Vector3d tip = grasp + frame.forces[h] * (m_scene_radius / m_reference_force);
    if ((tip - grasp).norm() > 1e-3 * m_scene_radius) {
      render::ArrowStyle style;
      style.color = m_options.force_color;
      style.always_on_top = true;
      rasterizer.draw_arrow(grasp, tip, style);
    }
  }
  if (summary != nullptr) *summary = counts;
  return rasterizer.image();
}

}  // namespace khz::run
