#pragma once
// Drawing a running scene with OpenGL (fixed function) from the haptic thread's snapshots.

#include <khz/reduced/subspace/embedded_surface.hpp>
#include <khz/render/camera.hpp>
#include <khz/run/frame_renderer.hpp>
#include <khz/run/scene_framing.hpp>
#include <khz/scene/scene_runtime.hpp>
#include <khz/viewer/scene_snapshot.hpp>
#include <khz/viewer/snapshot_points.hpp>

#include <Eigen/Geometry>

#include <memory>
#include <vector>

namespace khz::viewer {

/// Draws every object's surface, deformed to its q and placed at its pose; each contact pair's
/// pointshell points the query looked at (run::FrameOptions' traversed colour, hidden behind
/// surfaces) and those in contact (its contact colour, drawn over everything), as the frame
/// pictures do; the manipulandum of each hand (its device's point, joined to the grasp point by
/// the coupling's spring) and the contact force on each held object as an arrow from its grasp
/// point, scaled by ArrowScale to stay in view. Everything it needs of the runtime is copied at
/// construction, so drawing never touches the runtime the haptic thread runs: poses of objects
/// no hand holds are those at construction, reduced surfaces are deformed with their own
/// reduced::EmbeddedSurface, and the points are classified by SnapshotPoints.
class SceneView {
 public:
  /// Before the haptic loop starts. `layout` must outlive the view.
  /// @throws reduced::Error as reduced::EmbeddedSurface's constructor.
  SceneView(const scene::SceneRuntime& runtime, const SnapshotLayout& layout,
            const run::SceneFraming& framing);
  ~SceneView();

  /// The force arrows' ArrowScale::max_length: this fraction of view_half_extent() at the
  /// camera's target, or less where the grasp point has less room_in_view() along the force,
  /// `arrow_margin` pixels from the edges, so that every arrow stays in view.
  static constexpr double arrow_view_fraction = 0.5;
  static constexpr double arrow_margin = 12.0;

  /// Draws `snapshot` as `camera` sees it into the current OpenGL context's framebuffer
  /// (`width` × `height` pixels, the camera's aspect ratio). Allocates only to classify the
  /// points (SnapshotPoints::classify()).
  void draw(const SceneSnapshot& snapshot, const render::Camera& camera, int width, int height);

 private:
  struct Body;
  void draw_body(Body& body, const Eigen::Isometry3d& pose,
                 const Eigen::Map<const Eigen::VectorXd>& q) const;
  void draw_points(const SceneSnapshot& snapshot);
  void draw_hands(const SceneSnapshot& snapshot, const render::Camera& camera) const;

  const SnapshotLayout& m_layout;
  run::FrameOptions m_colors;  // FrameRenderer's colours
  SnapshotPoints m_points;
  std::vector<std::unique_ptr<Body>> m_bodies;
  std::vector<int> m_held_objects;                // per hand: the object it holds
  std::vector<Eigen::Vector3d> m_grasps_in_body;  // per hand
  double m_radius = 1.0;                          // the scene's (m)
  double m_reference_force;  // N drawn as long as the scene's radius (while short)
};

}  // namespace khz::viewer
