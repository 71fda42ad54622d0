#include <khz/reduced/fem/element_shape.hpp>

#include <Eigen/Geometry>
#include <Eigen/LU>

#include <cmath>

namespace khz::reduced {

double tet_signed_volume(const TetCorners& corners) noexcept {
  const Eigen::Vector3d e1 = (corners.row(1) - corners.row(0)).transpose();
  const Eigen::Vector3d e2 = (corners.row(2) - corners.row(0)).transpose();
  const Eigen::Vector3d e3 = (corners.row(3) - corners.row(0)).transpose();
  return e1.dot(e2.cross(e3)) / 6.0;
}

Eigen::Matrix<double, 4, 3, Eigen::RowMajor> tet_shape_gradients(
    const TetCorners& corners) noexcept {
  // φ_1..φ_3 are the coordinates of x − x0 in the edge basis: ∇φ_{1..3} are the rows of E⁻¹,
  // with E's columns the edges; φ_0 = 1 − φ_1 − φ_2 − φ_3.
  Eigen::Matrix3d edges;
  for (int k = 0; k < 3; ++k) edges.col(k) = (corners.row(k + 1) - corners.row(0)).transpose();
  const Eigen::Matrix3d inverse = edges.inverse();
  Eigen::Matrix<double, 4, 3, Eigen::RowMajor> gradients;
  gradients.bottomRows<3>() = inverse;
  gradients.row(0) = -inverse.colwise().sum();
  return gradients;
}

Eigen::Vector4d tet_barycentric(const TetCorners& corners, const Eigen::Vector3d& x) noexcept {
  Eigen::Matrix3d edges;
  for (int k = 0; k < 3; ++k) edges.col(k) = (corners.row(k + 1) - corners.row(0)).transpose();
  const Eigen::Vector3d local = edges.partialPivLu().solve(x - corners.row(0).transpose());
  return {1.0 - local.sum(), local.x(), local.y(), local.z()};
}

const Eigen::Matrix<double, 8, 3, Eigen::RowMajor>& hex_node_natural_coordinates() {
  static const Eigen::Matrix<double, 8, 3, Eigen::RowMajor> nodes = [] {
    Eigen::Matrix<double, 8, 3, Eigen::RowMajor> n;
    n << -1, -1, -1, 1, -1, -1, 1, 1, -1, -1, 1, -1,  //
        -1, -1, 1, 1, -1, 1, 1, 1, 1, -1, 1, 1;
    return n;
  }();
  return nodes;
}

Eigen::Matrix<double, 8, 1> hex_shape_values(const Eigen::Vector3d& xi) noexcept {
  const auto& nodes = hex_node_natural_coordinates();
  Eigen::Matrix<double, 8, 1> values;
  for (int a = 0; a < 8; ++a) {
    values[a] =
        0.125 * (1 + nodes(a, 0) * xi[0]) * (1 + nodes(a, 1) * xi[1]) * (1 + nodes(a, 2) * xi[2]);
  }
  return values;
}

Eigen::Matrix<double, 8, 3, Eigen::RowMajor> hex_shape_natural_derivatives(
    const Eigen::Vector3d& xi) noexcept {
  const auto& nodes = hex_node_natural_coordinates();
  Eigen::Matrix<double, 8, 3, Eigen::RowMajor> derivatives;
  for (int a = 0; a < 8; ++a) {
    const double fx = 1 + nodes(a, 0) * xi[0];
    const double fy = 1 + nodes(a, 1) * xi[1];
    const double fz = 1 + nodes(a, 2) * xi[2];
    derivatives.row(a) << 0.125 * nodes(a, 0) * fy * fz, 0.125 * nodes(a, 1) * fx * fz,
        0.125 * nodes(a, 2) * fx * fy;
  }
  return derivatives;
}

HexGradients hex_shape_gradients(const HexCorners& corners, const Eigen::Vector3d& xi) noexcept {
  const Eigen::Matrix<double, 8, 3, Eigen::RowMajor> natural = hex_shape_natural_derivatives(xi);
  // J_ik = ∂x_i/∂ξ_k; ∇φ_a = J⁻ᵀ ∂φ_a/∂ξ, i.e. row a of (∂φ/∂ξ) J⁻¹.
  const Eigen::Matrix3d jacobian = corners.transpose() * natural;
  HexGradients result;
  result.jacobian_determinant = jacobian.determinant();
  result.gradients = natural * jacobian.inverse();
  return result;
}

std::optional<Eigen::Vector3d> hex_natural_coordinates(const HexCorners& corners,
                                                       const Eigen::Vector3d& x) noexcept {
  constexpr int max_iterations = 30;
  const double scale = (corners.colwise().maxCoeff() - corners.colwise().minCoeff()).norm();
  Eigen::Vector3d xi = Eigen::Vector3d::Zero();
  for (int iteration = 0; iteration < max_iterations; ++iteration) {
    const Eigen::Vector3d residual = corners.transpose() * hex_shape_values(xi) - x;  // x(ξ) − x
    if (residual.norm() <= 1e-13 * scale) return xi;
    const Eigen::Matrix3d jacobian = corners.transpose() * hex_shape_natural_derivatives(xi);
    const Eigen::FullPivLU<Eigen::Matrix3d> lu(jacobian);
    if (!lu.isInvertible()) return std::nullopt;
    xi -= lu.solve(residual);
    if (!xi.allFinite() || xi.cwiseAbs().maxCoeff() > 1e6) return std::nullopt;
  }
  return std::nullopt;
}

const std::array<QuadraturePoint, 8>& hex_gauss_points() {
  static const std::array<QuadraturePoint, 8> points = [] {
    std::array<QuadraturePoint, 8> p;
    const double g = 1.0 / std::sqrt(3.0);
    const auto& nodes = hex_node_natural_coordinates();
    for (int a = 0; a < 8; ++a) p[a] = {g * nodes.row(a).transpose(), 1.0};
    return p;
  }();
  return points;
}

}  // namespace khz::reduced
