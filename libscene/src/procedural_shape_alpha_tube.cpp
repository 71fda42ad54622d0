// alpha_tube: a tube swept along an "α" curve with hemispherical ends (procedural_shape.hpp).
#include "procedural_shapes.hpp"
#include "ring_loft.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

namespace khz::scene::detail {
namespace {

constexpr double loop_height = 1.3;  // k: the loop's height (4k/√27 ≈ 1.0007) over its width
constexpr double tail_end = 1.15;    // τ: the curve parameter's end
constexpr double crossing_offset = 1.5;  // the crossing ends' z, in tube radii

/// The α curve c(t) (procedural_shape.hpp) and its unit tangent.
class AlphaCurve {
 public:
  AlphaCurve(double loop, double radius) : m_loop(loop), m_lift(crossing_offset * radius) {}

  Eigen::Vector3d point(double t) const {
    const double u = std::clamp(t, -1.0, 1.0);
    return {m_loop * (t * t - 0.5), m_loop * loop_height * t * (t * t - 1.0),
            m_lift * std::sin(std::numbers::pi / 2.0 * u)};
  }

  Eigen::Vector3d tangent(double t) const {
    const double lift = std::abs(t) < 1.0
                            ? m_lift * std::numbers::pi / 2.0 * std::cos(std::numbers::pi / 2.0 * t)
                            : 0.0;
    return Eigen::Vector3d(2.0 * m_loop * t, m_loop * loop_height * (3.0 * t * t - 1.0), lift)
        .normalized();
  }

 private:
  double m_loop;
  double m_lift;
};

/// Curve parameters of `segments` + 1 points at equal arc-length steps from −τ to τ, found on a
/// polyline 64 times finer.
std::vector<double> equal_arc_parameters(const AlphaCurve& curve, int segments) {
  const int fine = 64 * segments;
  std::vector<double> t(fine + 1);
  std::vector<double> length(fine + 1, 0.0);
  for (int i = 0; i <= fine; ++i) {
    t[i] = -tail_end + 2.0 * tail_end * i / fine;
    if (i > 0) length[i] = length[i - 1] + (curve.point(t[i]) - curve.point(t[i - 1])).norm();
  }
  std::vector<double> result(segments + 1);
  for (int i = 0; i <= segments; ++i) {
    const double target = length[fine] * i / segments;
    const auto above = std::lower_bound(length.begin() + 1, length.end() - 1, target);
    const auto k = above - length.begin();
    const double w = (target - length[k - 1]) / (length[k] - length[k - 1]);  // c' never vanishes
    result[i] = t[k - 1] + w * (t[k] - t[k - 1]);
  }
  result.front() = -tail_end;
  result.back() = tail_end;
  return result;
}

/// Writes the ring of `sides` points at `centre` with `radius`, perpendicular to the unit
/// `axis`, counter-clockwise about it, from row `row` on.
void write_ring(reduced::VertexMatrix& points, Eigen::Index row, const Eigen::Vector3d& centre,
                const Eigen::Vector3d& axis, double radius, int sides) {
  // The curve stays close to the xy plane (|axis.z| < 0.25), so z projected is a steady normal.
  const Eigen::Vector3d normal = (Eigen::Vector3d::UnitZ() - axis.z() * axis).normalized();
  const Eigen::Vector3d binormal = axis.cross(normal);
  for (int j = 0; j < sides; ++j) {
    const double angle = 2.0 * std::numbers::pi * j / sides;
    points.row(row + j) =
        (centre + radius * (std::cos(angle) * normal + std::sin(angle) * binormal)).transpose();
  }
}

reduced::TriangleMesh alpha_tube(double loop, double radius, int sides, int segments) {
  const AlphaCurve curve(loop, radius);
  const std::vector<double> t = equal_arc_parameters(curve, segments);
  const int caps = (sides + 3) / 4;  // latitude steps of a hemispherical end
  const Eigen::Vector3d first = curve.point(t.front()), first_axis = curve.tangent(t.front());
  const Eigen::Vector3d last = curve.point(t.back()), last_axis = curve.tangent(t.back());
  reduced::VertexMatrix points(Eigen::Index{sides} * (segments + 2 * caps - 1), 3);
  Eigen::Index row = 0;
  // Latitude ring m of the hemispherical end at `end`, which bulges along `side` × `axis`.
  const auto cap_ring = [&](const Eigen::Vector3d& end, const Eigen::Vector3d& axis, double side,
                            int m) {
    const double latitude = std::numbers::pi / 2.0 * m / caps;
    write_ring(points, row, end + side * radius * std::sin(latitude) * axis, axis,
               radius * std::cos(latitude), sides);
    row += sides;
  };
  for (int m = caps - 1; m >= 1; --m) cap_ring(first, first_axis, -1.0, m);
  for (const double ti : t) {
    write_ring(points, row, curve.point(ti), curve.tangent(ti), radius, sides);
    row += sides;
  }
  for (int m = 1; m < caps; ++m) cap_ring(last, last_axis, 1.0, m);
  return loft_between_poles(points, sides, (first - radius * first_axis).transpose(),
                            (last + radius * last_axis).transpose());
}

}  // namespace

ShapeGenerator read_alpha_tube(ShapeArguments& arguments) {
  const double loop = arguments.number("loop", 1.0, above(0.0));
  const double radius =
      arguments.number("radius", loop / 10.0,
                       with_text(open_closed(0.0, loop / 8.0),
                                 "a number in (0, " + format_number(loop / 8.0) + "] (loop/8)"));
  const int sides = arguments.integer("sides", 32, closed(8, 256));
  const int segments = arguments.integer("segments", 256, closed(16, 8192));
  return [=] { return alpha_tube(loop, radius, sides, segments); };
}

}  // namespace khz::scene::detail
