#include <khz/reduced/errors.hpp>
#include <khz/reduced/fem/element_shape.hpp>
#include <khz/reduced/mesh/element_quality.hpp>

#include <Eigen/Geometry>
#include <Eigen/LU>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <ostream>
#include <sstream>

namespace khz::reduced {
namespace {

/// What one element contributes to a QualityReport. `determinant` is the value the validity
/// rule classifies: the signed volume (tetrahedra) or the minimum corner det J (hexahedra).
struct ElementMeasure {
  double volume = 0.0;
  double quality = 0.0;
  double determinant = 0.0;
};

/// Angle between two vectors in [0, π], well conditioned near 0 and π (unlike acos of a
/// normalized dot product) and 0 if either vector vanishes.
double angle_between(const Eigen::Vector3d& u, const Eigen::Vector3d& v) {
  return std::atan2(u.cross(v).norm(), u.dot(v));
}

ElementMeasure measure_tetrahedron(const TetCorners& x) {
  // The dihedral angle at edge (a, b) is the angle between the half-planes through the edge
  // containing c and d; the normals e×(c−a) and e×(d−a) enclose the same angle.
  constexpr std::array<std::array<int, 4>, 6> edges = {
      {{0, 1, 2, 3}, {0, 2, 1, 3}, {0, 3, 1, 2}, {1, 2, 0, 3}, {1, 3, 0, 2}, {2, 3, 0, 1}}};
  double min_angle = std::numbers::pi;
  for (const auto& [a, b, c, d] : edges) {
    const Eigen::Vector3d e = (x.row(b) - x.row(a)).transpose();
    const Eigen::Vector3d to_c = (x.row(c) - x.row(a)).transpose();
    const Eigen::Vector3d to_d = (x.row(d) - x.row(a)).transpose();
    min_angle = std::min(min_angle, angle_between(e.cross(to_c), e.cross(to_d)));
  }
  const double volume = tet_signed_volume(x);
  return {volume, volume < 0 ? -min_angle : min_angle, volume};
}

/// ∂x/∂ξ of the trilinear map at natural point ξ.
Eigen::Matrix3d hex_jacobian(const HexCorners& x, const Eigen::Vector3d& xi) {
  return x.transpose() * hex_shape_natural_derivatives(xi);
}

ElementMeasure measure_hexahedron(const HexCorners& x) {
  ElementMeasure measure;
  for (const QuadraturePoint& point : hex_gauss_points()) {
    measure.volume += point.weight * hex_jacobian(x, point.xi).determinant();
  }
  // At a corner the columns of J are half the edge vectors leaving it (signed along +ξ), so
  // det J over the product of the column lengths is the scaled Jacobian of the three edges.
  measure.quality = 1.0;
  measure.determinant = std::numeric_limits<double>::infinity();
  for (int a = 0; a < 8; ++a) {
    const Eigen::Matrix3d jacobian =
        hex_jacobian(x, hex_node_natural_coordinates().row(a).transpose());
    const double determinant = jacobian.determinant();
    const double lengths = jacobian.col(0).norm() * jacobian.col(1).norm() * jacobian.col(2).norm();
    measure.quality = std::min(measure.quality, lengths > 0 ? determinant / lengths : 0.0);
    measure.determinant = std::min(measure.determinant, determinant);
  }
  return measure;
}

ElementMeasure measure_element(const VolumeMesh& mesh, Eigen::Index e) {
  if (mesh.element_type == ElementType::tetrahedron) {
    TetCorners corners;
    for (int a = 0; a < 4; ++a) corners.row(a) = mesh.vertices.row(mesh.elements(e, a));
    return measure_tetrahedron(corners);
  }
  HexCorners corners;
  for (int a = 0; a < 8; ++a) corners.row(a) = mesh.vertices.row(mesh.elements(e, a));
  return measure_hexahedron(corners);
}

double degeneracy_tolerance(const VolumeMesh& mesh) {
  if (mesh.num_vertices() == 0) return 0.0;
  const double diagonal =
      (mesh.vertices.colwise().maxCoeff() - mesh.vertices.colwise().minCoeff()).norm();
  return 1e-12 * diagonal * diagonal * diagonal;
}

bool is_inverted(double determinant, double tolerance) { return determinant < -tolerance; }
bool is_degenerate(double determinant, double tolerance) {
  return std::abs(determinant) <= tolerance;
}

}  // namespace

QualityReport analyze_elements(const VolumeMesh& mesh) {
  validate(mesh);
  QualityReport report;
  report.element_type = mesh.element_type;
  report.tolerance = degeneracy_tolerance(mesh);
  report.volume.reserve(mesh.num_elements());
  report.quality.reserve(mesh.num_elements());
  for (Eigen::Index e = 0; e < mesh.num_elements(); ++e) {
    const ElementMeasure measure = measure_element(mesh, e);
    report.volume.push_back(measure.volume);
    report.quality.push_back(measure.quality);
    const bool inverted = is_inverted(measure.determinant, report.tolerance);
    const bool degenerate = is_degenerate(measure.determinant, report.tolerance);
    report.num_inverted += inverted;
    report.num_degenerate += degenerate;
    if ((inverted || degenerate) && report.first_bad_element < 0) report.first_bad_element = e;
  }
  if (mesh.num_elements() == 0) return report;
  const auto [min_volume, max_volume] =
      std::minmax_element(report.volume.begin(), report.volume.end());
  const auto [min_quality, max_quality] =
      std::minmax_element(report.quality.begin(), report.quality.end());
  report.min_volume = *min_volume;
  report.max_volume = *max_volume;
  report.min_quality = *min_quality;
  report.max_quality = *max_quality;
  for (Eigen::Index e = 0; e < mesh.num_elements(); ++e) {
    report.total_volume += report.volume[e];
    report.mean_quality += report.quality[e];
  }
  report.mean_quality /= double(mesh.num_elements());
  return report;
}

std::ostream& operator<<(std::ostream& out, const QualityReport& report) {
  const bool tets = report.element_type == ElementType::tetrahedron;
  out << "elements:        " << report.volume.size() << (tets ? " tetrahedra" : " hexahedra")
      << "\nvolume:          " << report.total_volume << " (per element " << report.min_volume
      << " .. " << report.max_volume << ")\n"
      << (tets ? "min dihedral:    " : "scaled Jacobian: ") << report.min_quality << " .. "
      << report.max_quality << " (mean " << report.mean_quality << ")" << (tets ? " rad" : "")
      << "\ninverted:        " << report.num_inverted
      << "\ndegenerate:      " << report.num_degenerate << " (tolerance " << report.tolerance
      << ")\n";
  if (report.first_bad_element >= 0) {
    out << "first bad:       element " << report.first_bad_element << "\n";
  }
  return out;
}

void require_valid_elements(const VolumeMesh& mesh) {
  const QualityReport report = analyze_elements(mesh);
  const Eigen::Index e = report.first_bad_element;
  if (e < 0) return;
  const ElementMeasure measure = measure_element(mesh, e);
  std::ostringstream message;
  message << "element " << e << " is "
          << (is_inverted(measure.determinant, report.tolerance) ? "inverted" : "degenerate");
  if (mesh.element_type == ElementType::tetrahedron) {
    message << " (signed volume " << measure.volume << " m³";
  } else {
    message << " (minimum corner Jacobian determinant " << measure.determinant << " m³, volume "
            << measure.volume << " m³";
  }
  message << ", tolerance " << report.tolerance << " m³)";
  throw MeshError(message.str(), e);
}

}  // namespace khz::reduced
