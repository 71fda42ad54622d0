#pragma once
// Shape functions of the two element types: linear tetrahedra and trilinear hexahedra.

#include <khz/reduced/export.hpp>

#include <Eigen/Core>

#include <array>
#include <optional>

namespace khz::reduced {

/// Corner positions of a tetrahedron (rows, metres), node order as in VolumeMesh.
using TetCorners = Eigen::Matrix<double, 4, 3, Eigen::RowMajor>;
/// Corner positions of a hexahedron (rows, metres), VTK node order as in VolumeMesh.
using HexCorners = Eigen::Matrix<double, 8, 3, Eigen::RowMajor>;

/// Signed volume of a tetrahedron, (x1−x0)·((x2−x0)×(x3−x0))/6 (m³); positive when the node
/// order is positive.
KHZ_REDUCED_API double tet_signed_volume(const TetCorners& corners) noexcept;

/// Gradients ∇φ_a (row a, 1/m) of the four linear shape functions, constant over the element.
/// Undefined for a degenerate tetrahedron (zero volume): check tet_signed_volume() first.
KHZ_REDUCED_API Eigen::Matrix<double, 4, 3, Eigen::RowMajor> tet_shape_gradients(
    const TetCorners& corners) noexcept;

/// Barycentric coordinates (φ_0..φ_3) of point `x`; all in [0, 1] iff x is inside.
KHZ_REDUCED_API Eigen::Vector4d tet_barycentric(const TetCorners& corners,
                                                const Eigen::Vector3d& x) noexcept;

/// Natural coordinates ξ ∈ [−1, 1]³ of hexahedron node a (VTK order): row a.
KHZ_REDUCED_API const Eigen::Matrix<double, 8, 3, Eigen::RowMajor>& hex_node_natural_coordinates();

/// Trilinear shape function values φ_a(ξ) = ⅛ Π_k (1 + ξ_a,k ξ_k).
KHZ_REDUCED_API Eigen::Matrix<double, 8, 1> hex_shape_values(const Eigen::Vector3d& xi) noexcept;

/// Derivatives ∂φ_a/∂ξ_k (row a) with respect to the natural coordinates.
KHZ_REDUCED_API Eigen::Matrix<double, 8, 3, Eigen::RowMajor> hex_shape_natural_derivatives(
    const Eigen::Vector3d& xi) noexcept;

/// Physical gradients ∇φ_a (row a, 1/m) at natural point ξ and the Jacobian determinant
/// det(∂x/∂ξ) there (m³ per unit natural volume; ≤ 0 means inverted or degenerate there).
struct HexGradients {
  Eigen::Matrix<double, 8, 3, Eigen::RowMajor> gradients;
  double jacobian_determinant = 0.0;
};
KHZ_REDUCED_API HexGradients hex_shape_gradients(const HexCorners& corners,
                                                 const Eigen::Vector3d& xi) noexcept;

/// Natural coordinates of physical point `x` in the hexahedron, by Newton's method on the
/// trilinear map (exact in one step for parallelepipeds). Returns nothing if Newton does not
/// converge (x far outside a strongly distorted element); the result may lie outside [−1, 1]³
/// for points outside the element.
KHZ_REDUCED_API std::optional<Eigen::Vector3d> hex_natural_coordinates(
    const HexCorners& corners, const Eigen::Vector3d& x) noexcept;

/// One quadrature point on the reference element: natural coordinates and weight.
struct QuadraturePoint {
  Eigen::Vector3d xi;
  double weight = 0.0;
};

/// The 2×2×2 Gauss–Legendre rule on [−1, 1]³ (weights 1), exact for the trilinear hexahedron's
/// mass matrix and for its stiffness on parallelepipeds.
KHZ_REDUCED_API const std::array<QuadraturePoint, 8>& hex_gauss_points();

}  // namespace khz::reduced
