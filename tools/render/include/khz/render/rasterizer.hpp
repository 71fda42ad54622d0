#pragma once
// Draws triangle meshes, points and arrows into an image with a depth buffer (pure CPU).

#include <khz/reduced/mesh/triangle_mesh.hpp>
#include <khz/render/camera.hpp>
#include <khz/render/color.hpp>
#include <khz/render/image.hpp>

#include <Eigen/Core>

#include <span>
#include <vector>

namespace khz::render {

/// How draw_mesh() shades a surface: Lambert shading from a headlight (a point light at the
/// eye), two-sided, so open surfaces, inside-out meshes and inconsistently oriented triangles
/// all show their lit side. A surface facing the eye gets `color`; one seen edge-on gets
/// `ambient` × `color`.
struct MeshStyle {
  Color color{190, 190, 200};
  /// Brightness of a surface seen edge-on, as a fraction of `color`, in [0, 1].
  double ambient = 0.2;
  /// Gouraud shading from area-weighted vertex normals, for curved surfaces; false shades each
  /// triangle flat, which keeps sharp edges sharp (vertex normals average across them).
  bool smooth = false;
};

/// How draw_points() draws a point: a filled disc facing the eye, depth-tested as the front of
/// a sphere of the disc's size, so points lying on a drawn surface stay visible on it.
struct PointStyle {
  /// Disc radius in pixels, > 0. The pixel containing the point is always drawn.
  double radius = 3.0;
  /// Draw over everything, without depth test and without writing depth (an x-ray view: e.g.
  /// pointshell points in contact, which lie inside the other object); false hides points
  /// behind nearer geometry.
  bool always_on_top = false;
};

/// How draw_arrow() draws an arrow: a shaft as a thick line ending in a triangular head, both
/// sized in pixels so arrows stay legible at any distance.
struct ArrowStyle {
  Color color{220, 30, 30};
  /// Shaft width in pixels, > 0 (below 1, diagonal shafts may break up).
  double width = 2.5;
  /// Length of the head along the arrow, pixels, > 0. An arrow shorter than that on screen is
  /// all head, scaled down.
  double head_length = 12.0;
  /// Width of the head at its base, pixels, > 0.
  double head_width = 9.0;
  /// Draw over everything, without depth test and without writing depth; false hides the arrow
  /// behind nearer geometry.
  bool always_on_top = false;
};

/// Renders a scene through one camera into an RGB image and a depth buffer. Draw calls can come
/// in any order: every primitive is depth-tested (nearest wins, ties keep what was drawn first)
/// unless an option says otherwise. Geometry nearer than Camera::near_distance() is clipped
/// (triangles and arrows cut at that plane, points dropped); primitives with a non-finite
/// coordinate and triangles of zero projected area are skipped. No anti-aliasing; output is
/// deterministic. Set-up checks throw before anything is drawn.
class Rasterizer {
 public:
  /// An image of the camera's size filled with `background`, depth buffer empty.
  explicit Rasterizer(const Camera& camera, Color background = {255, 255, 255});

  const Camera& camera() const noexcept { return m_camera; }
  /// What has been drawn so far.
  const Image& image() const noexcept { return m_image; }
  /// Depth (distance along the viewing axis, world units) of the nearest depth-tested surface
  /// or point drawn at pixel (x, y), +∞ where there is none. Requires 0 ≤ x < width and
  /// 0 ≤ y < height (asserted in debug builds).
  double depth(int x, int y) const noexcept;

  /// Fills the image with `background` and empties the depth buffer.
  void clear(Color background) noexcept;

  /// Draws a triangle mesh.
  /// @param vertices #V×3 positions, world units. Triangles using a non-finite vertex are
  ///        skipped.
  /// @param triangles #F×3 zero-based indices into `vertices`; any winding.
  /// @throws khz::reduced::MeshError naming the triangle if an index is out of range;
  ///         khz::reduced::Error if style.ambient is not in [0, 1].
  void draw_mesh(const Eigen::Ref<const reduced::VertexMatrix>& vertices,
                 const Eigen::Ref<const reduced::TriangleMatrix>& triangles,
                 const MeshStyle& style = {});
  /// Draws `mesh` (its vertex colours are ignored); as above.
  void draw_mesh(const reduced::TriangleMesh& mesh, const MeshStyle& style = {});

  /// Draws points as discs, each in its own colour (for instance traversed, in contact or
  /// untouched pointshell points, thesis Fig. 3.1).
  /// @param points #P×3 positions, world units; non-finite ones are skipped.
  /// @param colors #P colours, one per point, or a single colour for all of them.
  /// @throws khz::reduced::Error if `colors` has another size (with #P > 0) or style.radius is
  ///         not positive and finite.
  void draw_points(const Eigen::Ref<const reduced::VertexMatrix>& points,
                   std::span<const Color> colors, const PointStyle& style = {});

  /// Draws an arrow from `tail` to `tip` (world units), for instance a force scaled to a length.
  /// Non-finite ends draw nothing; so does an arrow seen exactly end-on (zero length on screen).
  /// @throws khz::reduced::Error if a size in `style` is not positive and finite.
  void draw_arrow(const Eigen::Vector3d& tail, const Eigen::Vector3d& tip,
                  const ArrowStyle& style = {});

 private:
  Camera m_camera;
  Image m_image;
  /// 1/depth per pixel, 0 where nothing was drawn: 1/depth is affine in screen space, so it
  /// interpolates linearly across a triangle, and as a float it is finest near the eye.
  std::vector<float> m_inverse_depth;
};

}  // namespace khz::render
