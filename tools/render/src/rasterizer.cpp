#include <khz/render/rasterizer.hpp>

#include <khz/reduced/errors.hpp>

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <limits>
#include <string>

namespace khz::render {
namespace {

/// A corner ready for scan conversion: pixel position, 1/depth and shade in [0, 1].
struct ScreenVertex {
  double x;
  double y;
  double inverse_depth;
  double shade;
};

/// A corner before projection, for clipping at the near plane: view coordinates and shade.
struct ViewVertex {
  Eigen::Vector3d view;
  double shade;
};

/// The image and depth buffer being drawn into.
struct Target {
  Image& image;
  std::vector<float>& inverse_depth;
};

/// `color` × (ambient + (1 − ambient) × shade), rounded.
Color shaded(Color color, double ambient, double shade) {
  const double factor = ambient + (1.0 - ambient) * std::clamp(shade, 0.0, 1.0);
  const auto scale = [factor](std::uint8_t channel) {
    return static_cast<std::uint8_t>(std::lround(channel * factor));
  };
  return {scale(color.r), scale(color.g), scale(color.b)};
}

/// `value` rounded down into [low, high]; NaN gives `low`.
int clamp_to_int(double value, int low, int high) {
  if (!(value > low)) return low;
  if (value > high) return high;
  return static_cast<int>(std::floor(value));
}

/// The edge function of the directed edge from → to at a point: twice the signed area of the
/// triangle (from, to, point). It is always evaluated from the edge's lexicographically smaller
/// end and negated as needed, so the two triangles sharing an edge get bit-identical values of
/// opposite sign: a pixel centre on a shared edge belongs to both, never to neither.
class EdgeFunction {
 public:
  EdgeFunction(const ScreenVertex& from, const ScreenVertex& to) {
    const bool swap = to.x < from.x || (to.x == from.x && to.y < from.y);
    const ScreenVertex& start = swap ? to : from;
    const ScreenVertex& end = swap ? from : to;
    m_x = start.x;
    m_y = start.y;
    m_dx = end.x - start.x;
    m_dy = end.y - start.y;
    m_sign = swap ? -1.0 : 1.0;
  }
  double operator()(double px, double py) const {
    return m_sign * (m_dx * (py - m_y) - m_dy * (px - m_x));
  }

 private:
  double m_x, m_y, m_dx, m_dy, m_sign;
};

/// Scan-converts a triangle: every pixel whose centre lies inside or on its boundary gets
/// `color` × (ambient + (1 − ambient) × shade), shade interpolated perspective-correctly, where
/// it passes the depth test (or everywhere, without depth test and without writing depth).
void fill_triangle(Target& target, const ScreenVertex& a, const ScreenVertex& b,
                   const ScreenVertex& c, Color color, double ambient, bool depth_test) {
  const double area = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
  if (!std::isfinite(area) || area == 0.0) return;
  const int width = target.image.width();
  const int height = target.image.height();
  // Pixel i has its centre at i + 0.5: the columns with centres in [min x, max x].
  const int x_begin = clamp_to_int(std::ceil(std::min({a.x, b.x, c.x}) - 0.5), 0, width);
  const int x_end = clamp_to_int(std::floor(std::max({a.x, b.x, c.x}) - 0.5) + 1.0, 0, width);
  const int y_begin = clamp_to_int(std::ceil(std::min({a.y, b.y, c.y}) - 0.5), 0, height);
  const int y_end = clamp_to_int(std::floor(std::max({a.y, b.y, c.y}) - 0.5) + 1.0, 0, height);
  if (x_begin >= x_end || y_begin >= y_end) return;

  const EdgeFunction opposite_a(b, c);
  const EdgeFunction opposite_b(c, a);
  const EdgeFunction opposite_c(a, b);
  const double inverse_area = 1.0 / area;
  const bool flat = a.shade == b.shade && b.shade == c.shade;
  const Color flat_color = shaded(color, ambient, a.shade);
  std::uint8_t* const pixels = target.image.bytes().data();
  float* const depths = target.inverse_depth.data();

  for (int y = y_begin; y < y_end; ++y) {
    const double py = y + 0.5;
    for (int x = x_begin; x < x_end; ++x) {
      const double px = x + 0.5;
      // Barycentric coordinates; dividing by the signed area makes "inside" mean all ≥ 0 for
      // either winding without changing the signs the shared-edge rule relies on.
      const double la = opposite_a(px, py) * inverse_area;
      const double lb = opposite_b(px, py) * inverse_area;
      const double lc = opposite_c(px, py) * inverse_area;
      if (la < 0.0 || lb < 0.0 || lc < 0.0) continue;
      const double inverse_depth =
          la * a.inverse_depth + lb * b.inverse_depth + lc * c.inverse_depth;
      const std::size_t index = static_cast<std::size_t>(y) * static_cast<std::size_t>(width) +
                                static_cast<std::size_t>(x);
      if (depth_test) {
        const auto depth = static_cast<float>(inverse_depth);
        if (!(depth > depths[index])) continue;
        depths[index] = depth;
      }
      Color pixel = flat_color;
      if (!flat) {
        const double shade = (la * a.inverse_depth * a.shade + lb * b.inverse_depth * b.shade +
                              lc * c.inverse_depth * c.shade) /
                             inverse_depth;
        pixel = shaded(color, ambient, shade);
      }
      std::uint8_t* const p = pixels + 3 * index;
      p[0] = pixel.r;
      p[1] = pixel.g;
      p[2] = pixel.b;
    }
  }
}

/// Fills the pixels whose centres lie within `radius` of (x, y), and the pixel containing
/// (x, y), at depth 1 / inverse_depth.
void fill_disc(Target& target, double x, double y, double radius, double inverse_depth, Color color,
               bool depth_test) {
  const int width = target.image.width();
  const int height = target.image.height();
  const double centre_x = std::floor(x);
  const double centre_y = std::floor(y);
  const int x_begin = clamp_to_int(std::min(std::ceil(x - radius - 0.5), centre_x), 0, width);
  const int x_end = clamp_to_int(std::max(std::floor(x + radius - 0.5), centre_x) + 1.0, 0, width);
  const int y_begin = clamp_to_int(std::min(std::ceil(y - radius - 0.5), centre_y), 0, height);
  const int y_end = clamp_to_int(std::max(std::floor(y + radius - 0.5), centre_y) + 1.0, 0, height);
  const auto depth = static_cast<float>(inverse_depth);
  for (int iy = y_begin; iy < y_end; ++iy) {
    const double dy = iy + 0.5 - y;
    for (int ix = x_begin; ix < x_end; ++ix) {
      const double dx = ix + 0.5 - x;
      if (dx * dx + dy * dy > radius * radius && (ix != centre_x || iy != centre_y)) continue;
      const std::size_t index = static_cast<std::size_t>(iy) * static_cast<std::size_t>(width) +
                                static_cast<std::size_t>(ix);
      if (depth_test) {
        if (!(depth > target.inverse_depth[index])) continue;
        target.inverse_depth[index] = depth;
      }
      target.image.set_pixel(ix, iy, color);
    }
  }
}

ScreenVertex to_screen(const Camera& camera, const ViewVertex& vertex) {
  const Eigen::Vector2d pixel = camera.view_to_pixel(vertex.view);
  return {pixel.x(), pixel.y(), 1.0 / vertex.view.z(), vertex.shade};
}

/// Draws a triangle with at least one corner nearer than the near plane: Sutherland–Hodgman
/// against that plane leaves a triangle or a quadrilateral, drawn as a fan.
void fill_clipped_triangle(Target& target, const Camera& camera,
                           const std::array<ViewVertex, 3>& corners, Color color, double ambient) {
  const double near = camera.near_distance();
  std::array<ViewVertex, 4> kept;
  int count = 0;
  for (int i = 0; i < 3; ++i) {
    const ViewVertex& p = corners[i];
    const ViewVertex& q = corners[(i + 1) % 3];
    const bool p_in = p.view.z() >= near;
    if (p_in) kept[count++] = p;
    if (p_in != (q.view.z() >= near)) {
      const double t = (near - p.view.z()) / (q.view.z() - p.view.z());
      ViewVertex cut{p.view + t * (q.view - p.view), p.shade + t * (q.shade - p.shade)};
      cut.view.z() = near;
      kept[count++] = cut;
    }
  }
  for (int i = 1; i + 1 < count; ++i) {
    fill_triangle(target, to_screen(camera, kept[0]), to_screen(camera, kept[i]),
                  to_screen(camera, kept[i + 1]), color, ambient, true);
  }
}

/// |cos| of the angle between a normal and the direction from `point` to the eye (at the view
/// origin): two-sided Lambert under a headlight. 0 for a zero normal.
double headlight(const Eigen::Vector3d& normal, const Eigen::Vector3d& point) {
  const double norms = normal.norm() * point.norm();
  return norms > 0.0 ? std::abs(normal.dot(point)) / norms : 0.0;
}

void require_positive(double value, const char* what) {
  if (!(std::isfinite(value) && value > 0.0)) {
    throw reduced::Error(std::string(what) + " " + std::to_string(value) +
                         " is not positive and finite");
  }
}

}  // namespace

Rasterizer::Rasterizer(const Camera& camera, Color background)
    : m_camera(camera),
      m_image(camera.width(), camera.height(), background),
      m_inverse_depth(
          static_cast<std::size_t>(camera.width()) * static_cast<std::size_t>(camera.height()),
          0.0f) {}

double Rasterizer::depth(int x, int y) const noexcept {
  assert(x >= 0 && x < m_image.width() && y >= 0 && y < m_image.height());
  const float inverse_depth =
      m_inverse_depth[static_cast<std::size_t>(y) * static_cast<std::size_t>(m_image.width()) +
                      static_cast<std::size_t>(x)];
  return inverse_depth > 0.0f ? 1.0 / inverse_depth : std::numeric_limits<double>::infinity();
}

void Rasterizer::clear(Color background) noexcept {
  m_image.fill(background);
  std::fill(m_inverse_depth.begin(), m_inverse_depth.end(), 0.0f);
}

void Rasterizer::draw_mesh(const Eigen::Ref<const reduced::VertexMatrix>& vertices,
                           const Eigen::Ref<const reduced::TriangleMatrix>& triangles,
                           const MeshStyle& style) {
  if (!(style.ambient >= 0.0 && style.ambient <= 1.0)) {
    throw reduced::Error("draw_mesh: ambient " + std::to_string(style.ambient) +
                         " is not in [0, 1]");
  }
  const Eigen::Index vertex_count = vertices.rows();
  for (Eigen::Index t = 0; t < triangles.rows(); ++t) {
    for (int k = 0; k < 3; ++k) {
      const int index = triangles(t, k);
      if (index < 0 || index >= vertex_count) {
        throw reduced::MeshError("draw_mesh: triangle " + std::to_string(t) + " has vertex index " +
                                     std::to_string(index) + " outside [0, " +
                                     std::to_string(vertex_count) + ")",
                                 t);
      }
    }
  }

  // Everything below works in view coordinates (eye at the origin), where the headlight
  // direction at a point is the point itself.
  std::vector<ViewVertex> view_vertices(static_cast<std::size_t>(vertex_count));
  for (Eigen::Index i = 0; i < vertex_count; ++i) {
    view_vertices[i].view = m_camera.to_view(vertices.row(i).transpose());
    view_vertices[i].shade = 0.0;
  }
  const auto finite = [&view_vertices](int i) { return view_vertices[i].view.allFinite(); };
  const auto face_normal = [&view_vertices](int a, int b, int c) -> Eigen::Vector3d {
    return (view_vertices[b].view - view_vertices[a].view)
        .cross(view_vertices[c].view - view_vertices[a].view);
  };
  if (style.smooth) {
    // Area-weighted vertex normals: the unnormalized face normal is twice the area.
    std::vector<Eigen::Vector3d> normals(view_vertices.size(), Eigen::Vector3d::Zero());
    for (Eigen::Index t = 0; t < triangles.rows(); ++t) {
      const int a = triangles(t, 0), b = triangles(t, 1), c = triangles(t, 2);
      if (!finite(a) || !finite(b) || !finite(c)) continue;
      const Eigen::Vector3d normal = face_normal(a, b, c);
      normals[a] += normal;
      normals[b] += normal;
      normals[c] += normal;
    }
    for (std::size_t i = 0; i < view_vertices.size(); ++i) {
      view_vertices[i].shade = headlight(normals[i], view_vertices[i].view);
    }
  }
  const double near = m_camera.near_distance();
  std::vector<ScreenVertex> screen(view_vertices.size());
  for (std::size_t i = 0; i < view_vertices.size(); ++i) {
    if (view_vertices[i].view.z() >= near) screen[i] = to_screen(m_camera, view_vertices[i]);
  }

  Target target{m_image, m_inverse_depth};
  for (Eigen::Index t = 0; t < triangles.rows(); ++t) {
    const int a = triangles(t, 0), b = triangles(t, 1), c = triangles(t, 2);
    if (!finite(a) || !finite(b) || !finite(c)) continue;
    std::array<ViewVertex, 3> corners{view_vertices[a], view_vertices[b], view_vertices[c]};
    if (!style.smooth) {
      const Eigen::Vector3d centroid = (corners[0].view + corners[1].view + corners[2].view) / 3.0;
      const double shade = headlight(face_normal(a, b, c), centroid);
      for (ViewVertex& corner : corners) corner.shade = shade;
    }
    const int in_front = (corners[0].view.z() >= near) + (corners[1].view.z() >= near) +
                         (corners[2].view.z() >= near);
    if (in_front == 3) {
      // The shared projected corners keep adjacent triangles watertight (see EdgeFunction).
      ScreenVertex sa = screen[a], sb = screen[b], sc = screen[c];
      sa.shade = corners[0].shade;
      sb.shade = corners[1].shade;
      sc.shade = corners[2].shade;
      fill_triangle(target, sa, sb, sc, style.color, style.ambient, true);
    } else if (in_front > 0) {
      fill_clipped_triangle(target, m_camera, corners, style.color, style.ambient);
    }
  }
}

void Rasterizer::draw_mesh(const reduced::TriangleMesh& mesh, const MeshStyle& style) {
  draw_mesh(mesh.vertices, mesh.triangles, style);
}

void Rasterizer::draw_points(const Eigen::Ref<const reduced::VertexMatrix>& points,
                             std::span<const Color> colors, const PointStyle& style) {
  require_positive(style.radius, "draw_points: radius");
  const auto count = static_cast<std::size_t>(points.rows());
  if (count > 0 && colors.size() != 1 && colors.size() != count) {
    throw reduced::Error("draw_points: " + std::to_string(colors.size()) + " colours for " +
                         std::to_string(count) + " points (expected 1 or " + std::to_string(count) +
                         ")");
  }
  Target target{m_image, m_inverse_depth};
  for (std::size_t i = 0; i < count; ++i) {
    const std::optional<ScreenPoint> point =
        m_camera.project(points.row(static_cast<Eigen::Index>(i)).transpose());
    if (!point) continue;
    // The front of a sphere whose silhouette is the disc.
    const double world_radius = style.radius * point->depth / m_camera.focal_length();
    const double front = std::max(point->depth - world_radius, m_camera.near_distance());
    fill_disc(target, point->pixel.x(), point->pixel.y(), style.radius, 1.0 / front,
              colors[colors.size() == 1 ? 0 : i], !style.always_on_top);
  }
}

void Rasterizer::draw_arrow(const Eigen::Vector3d& tail, const Eigen::Vector3d& tip,
                            const ArrowStyle& style) {
  require_positive(style.width, "draw_arrow: width");
  require_positive(style.head_length, "draw_arrow: head_length");
  require_positive(style.head_width, "draw_arrow: head_width");
  if (!tail.allFinite() || !tip.allFinite()) return;
  Eigen::Vector3d start = m_camera.to_view(tail);
  Eigen::Vector3d end = m_camera.to_view(tip);
  const double near = m_camera.near_distance();
  if (start.z() < near && end.z() < near) return;
  if (start.z() < near) start += (near - start.z()) / (end.z() - start.z()) * (end - start);
  if (end.z() < near) end += (near - end.z()) / (start.z() - end.z()) * (start - end);

  const Eigen::Vector2d p0 = m_camera.view_to_pixel(start);
  const Eigen::Vector2d p1 = m_camera.view_to_pixel(end);
  const double length = (p1 - p0).norm();
  if (!(length > 0.0)) return;
  const Eigen::Vector2d along = (p1 - p0) / length;
  const Eigen::Vector2d across(-along.y(), along.x());
  const double head_length = std::min(style.head_length, length);
  const double head_width = style.head_width * head_length / style.head_length;
  const Eigen::Vector2d base = p1 - head_length * along;
  // 1/depth is affine along a projected segment, so the head's base gets it by interpolation.
  const double w0 = 1.0 / start.z();
  const double w1 = 1.0 / end.z();
  const double w_base = w0 + (w1 - w0) * (length - head_length) / length;
  const auto corner = [](const Eigen::Vector2d& p, double inverse_depth) {
    return ScreenVertex{p.x(), p.y(), inverse_depth, 1.0};
  };

  Target target{m_image, m_inverse_depth};
  const bool depth_test = !style.always_on_top;
  const Eigen::Vector2d half_shaft = 0.5 * style.width * across;
  if (length > head_length) {
    const ScreenVertex t0 = corner(p0 + half_shaft, w0), t1 = corner(p0 - half_shaft, w0);
    const ScreenVertex b0 = corner(base + half_shaft, w_base);
    const ScreenVertex b1 = corner(base - half_shaft, w_base);
    fill_triangle(target, t0, t1, b1, style.color, 1.0, depth_test);
    fill_triangle(target, t0, b1, b0, style.color, 1.0, depth_test);
  }
  const Eigen::Vector2d half_head = 0.5 * head_width * across;
  fill_triangle(target, corner(base + half_head, w_base), corner(base - half_head, w_base),
                corner(p1, w1), style.color, 1.0, depth_test);
}

}  // namespace khz::render
