#pragma once
// Pictures of a running scene: every object's (deformed) surface, the pointshell points the
// contact query looked at and those in contact (thesis Figure 3.1), and the contact force.

#include <khz/render/camera.hpp>
#include <khz/render/color.hpp>
#include <khz/render/image.hpp>
#include <khz/run/frame_content.hpp>
#include <khz/scene/scene_runtime.hpp>

#include <filesystem>

namespace khz::run {

/// Options of FrameRenderer.
struct FrameOptions {
  int width = 800;   ///< Pixels, ≥ 16.
  int height = 600;  ///< Pixels, ≥ 16.
  /// Direction from the scene's centre to the eye (need not be unit, not parallel to `up`). The
  /// eye is placed where the scene's bounding sphere just fits the view. This and `up` are world
  /// directions in a scene whose up is y, and are turned with it in one with free objects under
  /// another gravity (SceneFraming::up, turned()).
  Eigen::Vector3d view_direction{1.0, 0.8, 1.6};
  Eigen::Vector3d up = Eigen::Vector3d::UnitY();  ///< Direction shown upwards.
  render::Color held_color{120, 160, 230};        ///< The held objects' surfaces.
  render::Color free_color{150, 205, 140};        ///< Free objects' (scene "dynamics").
  render::Color other_color{200, 200, 195};       ///< Every other object's surface.
  render::Color traversed_color{250, 200, 40};    ///< Points looked at, not in contact.
  render::Color contact_color{220, 30, 30};       ///< Points in contact (stuck, or no friction).
  render::Color sliding_color{40, 90, 230};       ///< Points in contact whose friction slid.
  render::Color force_color{20, 150, 40};         ///< The contact force arrow.
  /// Newtons drawn as an arrow as long as the scene's radius; 0 picks the coupling's
  /// saturation force, or 1 N when it has none.
  double arrow_force = 0.0;
};

/// Whether a surface is shaded smoothly (vertex normals) in pictures: finely triangulated
/// (curved) ones are; coarse ones, boxes say, keep their edges.
bool shade_smoothly(const reduced::TriangleMatrix& triangles) noexcept;

/// The colour `options` give object `object`'s surface in pictures: held_color if a hand holds
/// it, free_color if it is free (scene "dynamics"), other_color otherwise.
render::Color surface_color(const FrameOptions& options, const scene::SceneRuntime& runtime,
                            int object);

/// The force (N) drawn as an arrow as long as the scene's radius: `arrow_force` if positive,
/// else the coupling's saturation force if it has one, else 1 N.
double arrow_reference_force(const scene::SceneDescription& scene, double arrow_force = 0.0);

/// What a frame showed, for checks and captions.
struct FrameSummary {
  std::int64_t traversed = 0;   ///< Points drawn as looked at (all pairs).
  std::int64_t in_contact = 0;  ///< Points drawn as in contact, sliding ones included.
  std::int64_t sliding = 0;     ///< Of those, the points drawn as sliding.
};

/// Renders frames of one scene::SceneRuntime through a camera fixed at construction (framing the
/// scene's objects at their start poses, so frames of a run line up).
class FrameRenderer {
 public:
  /// @throws reduced::Error if the options are invalid.
  FrameRenderer(const scene::SceneRuntime& runtime, const FrameOptions& options = {});

  const render::Camera& camera() const noexcept { return m_camera; }

  /// A frame of the runtime it was made for (capture_frame()): the surfaces, each contact
  /// pair's points looked at and in contact (untouched points are not drawn), and the contact
  /// force on each held object as an arrow at its grasp point.
  /// @param summary if not null, receives the point counts.
  render::Image render(const FrameContent& frame, FrameSummary* summary = nullptr) const;

 private:
  FrameOptions m_options;
  std::vector<render::Color> m_colors;               // per object: held, free or other
  std::vector<reduced::TriangleMatrix> m_triangles;  // per object
  double m_reference_force = 1.0;                    // N drawn as long as the scene's radius
  double m_scene_radius = 0.0;  // set while m_camera is made: declared before it
  render::Camera m_camera;
};

}  // namespace khz::run
