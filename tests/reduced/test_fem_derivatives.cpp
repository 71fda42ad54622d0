// Finite-difference checks of the FEM model's derivatives on distorted tetrahedral and
// hexahedral boxes under large deformations: R = ∇energy, K = ∇R, (H : v) = d/dε K(εv)|₀.
#include <khz/reduced/fem/fem_model.hpp>
#include <khz/reduced/meshing/box_mesh.hpp>

#include <khz/test/element_types.hpp>

#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <random>

namespace khz::reduced {
namespace {

constexpr double cell_size = 0.5;

/// A 2×2×2-cell box with every vertex moved randomly by up to 15% of a cell, so no element has
/// the special symmetry of the generated lattice.
VolumeMesh distorted_box(ElementType type) {
  const Eigen::Vector3d min_corner(0, 0, 0), max_corner(1, 1, 1);
  const Eigen::Vector3i cells(2, 2, 2);
  VolumeMesh mesh = type == ElementType::tetrahedron ? box_tet_mesh(min_corner, max_corner, cells)
                                                     : box_hex_mesh(min_corner, max_corner, cells);
  std::mt19937 random(11);
  std::uniform_real_distribution<double> jitter(-0.15 * cell_size, 0.15 * cell_size);
  for (Eigen::Index v = 0; v < mesh.num_vertices(); ++v) {
    for (int i = 0; i < 3; ++i) mesh.vertices(v, i) += jitter(random);
  }
  return mesh;
}

/// StVK plus a random positive semi-definite part, so every entry of C matters.
Material anisotropic_material() {
  const LameParameters lame = lame_from_young_poisson(1e5, 0.3);
  std::mt19937 random(5);
  std::uniform_real_distribution<double> entry(-1.0, 1.0);
  VoigtMatrix a;
  for (int i = 0; i < 36; ++i) a(i) = entry(random);
  return Material::general(stvk_elasticity(lame) + 0.2 * lame.mu * a * a.transpose(), 1000.0);
}

/// u = (R − I) X + noise: a rotation by 1.2 rad about a skew axis plus random displacements of
/// 0.3 cell sizes, so both the rotation and the strain are large.
Eigen::VectorXd large_deformation(const VolumeMesh& mesh, unsigned seed) {
  const Eigen::Matrix3d rotation =
      Eigen::AngleAxisd(1.2, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> noise(-0.3 * cell_size, 0.3 * cell_size);
  Eigen::VectorXd u(3 * mesh.num_vertices());
  for (Eigen::Index v = 0; v < mesh.num_vertices(); ++v) {
    const Eigen::Vector3d x = mesh.vertices.row(v).transpose();
    u.segment<3>(3 * v) = (rotation - Eigen::Matrix3d::Identity()) * x;
    for (int i = 0; i < 3; ++i) u[3 * v + i] += noise(random);
  }
  return u;
}

double relative_error(const Eigen::MatrixXd& value, const Eigen::MatrixXd& reference) {
  return (value - reference).norm() / reference.norm();
}

Eigen::VectorXd forces(const FemModel& model, const Eigen::VectorXd& u) {
  Eigen::VectorXd result;
  model.internal_forces(u, result);
  return result;
}

Eigen::MatrixXd stiffness(const FemModel& model, const Eigen::VectorXd& u) {
  SparseMatrix k = model.stiffness_pattern();
  model.tangent_stiffness(u, k);
  return Eigen::MatrixXd(k);
}

class FemDerivatives : public ::testing::TestWithParam<ElementType> {
 protected:
  FemModel model{distorted_box(GetParam()), {anisotropic_material()}};
  Eigen::VectorXd u = large_deformation(model.mesh(), 3);
  // Central-difference step: truncation error ~ step², round-off ~ 1e-16 / step; 1e-6 m on
  // displacements of ~0.5 m balances them.
  double step = 1e-6;
};

// Measured relative errors (2-norm) of the central differences: 1.2e-10 (tetrahedra), 1.5e-10
// (hexahedra).
TEST_P(FemDerivatives, ForcesAreTheEnergyGradient) {
  const Eigen::VectorXd analytic = forces(model, u);
  Eigen::VectorXd numeric(u.size());
  for (Eigen::Index i = 0; i < u.size(); ++i) {
    Eigen::VectorXd plus = u, minus = u;
    plus[i] += step;
    minus[i] -= step;
    numeric[i] = (model.strain_energy(plus) - model.strain_energy(minus)) / (2 * step);
  }
  EXPECT_LT(relative_error(numeric, analytic), 5e-9);
}

// Measured relative errors (Frobenius): 5.2e-11 (tetrahedra), 4.7e-11 (hexahedra).
TEST_P(FemDerivatives, StiffnessIsTheForceJacobian) {
  const Eigen::MatrixXd analytic = stiffness(model, u);
  Eigen::MatrixXd numeric(u.size(), u.size());
  for (Eigen::Index j = 0; j < u.size(); ++j) {
    Eigen::VectorXd plus = u, minus = u;
    plus[j] += step;
    minus[j] -= step;
    numeric.col(j) = (forces(model, plus) - forces(model, minus)) / (2 * step);
  }
  EXPECT_LT(relative_error(numeric, analytic), 2e-9);
}

// K is symmetric by construction (Bᵀ C B plus a scalar-times-identity geometric part); measured
// relative asymmetry 1e-16, i.e. round-off.
TEST_P(FemDerivatives, StiffnessIsSymmetric) {
  const Eigen::MatrixXd k = stiffness(model, u);
  EXPECT_LT(relative_error(k.transpose(), k), 1e-14);
}

// For a linear material K(εv) is a quadratic polynomial in ε, so the central difference
// (K(εv) − K(−εv)) / 2ε equals d/dε K(εv)|₀ up to round-off whatever ε: measured relative
// errors 6.3e-14 (tetrahedra), 5.0e-14 (hexahedra) with ε = 1e-3.
TEST_P(FemDerivatives, HessianContractionIsTheStiffnessDerivative) {
  const Eigen::VectorXd v = large_deformation(model.mesh(), 8);
  const Eigen::MatrixXd analytic = Eigen::MatrixXd(model.hessian_contraction(v));
  const double epsilon = 1e-3;
  const Eigen::MatrixXd numeric =
      (stiffness(model, epsilon * v) - stiffness(model, -epsilon * v)) / (2 * epsilon);
  EXPECT_LT(relative_error(numeric, analytic), 1e-12);
}

// Measured relative difference 3e-16.
TEST_P(FemDerivatives, HessianContractionIsLinearInTheDirection) {
  const Eigen::VectorXd v = large_deformation(model.mesh(), 8);
  const Eigen::VectorXd w = large_deformation(model.mesh(), 9);
  const Eigen::MatrixXd combined = Eigen::MatrixXd(model.hessian_contraction(2.0 * v - 3.0 * w));
  const Eigen::MatrixXd separate = 2.0 * Eigen::MatrixXd(model.hessian_contraction(v)) -
                                   3.0 * Eigen::MatrixXd(model.hessian_contraction(w));
  EXPECT_LT(relative_error(combined, separate), 1e-14);
}

INSTANTIATE_TEST_SUITE_P(ElementTypes, FemDerivatives, ::testing::ValuesIn(test::all_element_types),
                         test::element_type_name);

}  // namespace
}  // namespace khz::reduced
