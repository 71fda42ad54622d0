// Patch tests: a uniform deformation u = (F − I) X of a block with distorted interior elements
// must be reproduced exactly — uniform F (hence E and S = C:E) at every quadrature point, zero
// net force at interior vertices, and the analytic traction P·n·area on a face.
#include <khz/reduced/fem/fem_model.hpp>
#include <khz/reduced/meshing/box_mesh.hpp>

#include <khz/test/element_types.hpp>

#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <random>

namespace khz::reduced {
namespace {

constexpr int cells = 3;

bool on_boundary(const Eigen::RowVector3d& x) {
  return (x.array() == 0.0).any() || (x.array() == 1.0).any();
}

/// The unit cube in 3×3×3 cells with its interior vertices moved by up to 20% of a cell, so the
/// elements are general (hexahedra no longer parallelepipeds) while the faces stay planar.
VolumeMesh distorted_block(ElementType type) {
  const Eigen::Vector3d min_corner(0, 0, 0), max_corner(1, 1, 1);
  const Eigen::Vector3i counts(cells, cells, cells);
  VolumeMesh mesh = type == ElementType::tetrahedron ? box_tet_mesh(min_corner, max_corner, counts)
                                                     : box_hex_mesh(min_corner, max_corner, counts);
  std::mt19937 random(9);
  std::uniform_real_distribution<double> jitter(-0.2 / cells, 0.2 / cells);
  for (Eigen::Index v = 0; v < mesh.num_vertices(); ++v) {
    if (on_boundary(mesh.vertices.row(v))) continue;
    for (int i = 0; i < 3; ++i) mesh.vertices(v, i) += jitter(random);
  }
  return mesh;
}

class FemPatch : public ::testing::TestWithParam<ElementType> {
 protected:
  FemPatch() {
    deformation << 1.2, 0.1, 0.05,  //
        0.15, 0.9, 0.1,             //
        -0.05, 0.2, 1.1;
    VoigtMatrix c = stvk_elasticity(lame_from_young_poisson(2e6, 0.3));
    c(2, 4) = c(4, 2) = 2e5;  // anisotropic coupling
    elasticity = c;
    u.resize(3 * mesh.num_vertices());
    for (Eigen::Index v = 0; v < mesh.num_vertices(); ++v) {
      u.segment<3>(3 * v) =
          (deformation - Eigen::Matrix3d::Identity()) * mesh.vertices.row(v).transpose();
    }
    // Analytic stress: E = ½(FᵀF − I), S = C:E in Voigt form, P = F S.
    const Eigen::Matrix3d e =
        0.5 * (deformation.transpose() * deformation - Eigen::Matrix3d::Identity());
    Eigen::Matrix<double, 6, 1> e_voigt;
    e_voigt << e(0, 0), e(1, 1), e(2, 2), 2 * e(1, 2), 2 * e(0, 2), 2 * e(0, 1);
    const Eigen::Matrix<double, 6, 1> s = elasticity * e_voigt;
    Eigen::Matrix3d stress;
    stress << s[0], s[5], s[4], s[5], s[1], s[3], s[4], s[3], s[2];
    first_piola = deformation * stress;
  }

  VolumeMesh mesh = distorted_block(GetParam());
  Eigen::Matrix3d deformation;
  VoigtMatrix elasticity;
  Eigen::Matrix3d first_piola;
  Eigen::VectorXd u;
};

// Measured: max |F_q − F| = 4.4e-16 (tetrahedra and hexahedra).
TEST_P(FemPatch, DeformationGradientIsUniformAtEveryQuadraturePoint) {
  const FemModel model(mesh, {Material::general(elasticity, 1.0)});
  double worst = 0.0;
  for (Eigen::Index e = 0; e < mesh.num_elements(); ++e) {
    for (int q = 0; q < model.quadrature_points_per_element(); ++q) {
      const auto gradients = model.shape_gradients(e, q);
      Eigen::Matrix3d f = Eigen::Matrix3d::Identity();
      for (Eigen::Index a = 0; a < gradients.rows(); ++a) {
        f += u.segment<3>(3 * mesh.elements(e, a)) * gradients.row(a);
      }
      worst = std::max(worst, (f - deformation).cwiseAbs().maxCoeff());
    }
  }
  EXPECT_LT(worst, 1e-14);
}

// Strain energy of a uniform state is ½ E:S · volume. Measured relative error 1.8e-16
// (tetrahedra), 5.5e-16 (hexahedra).
TEST_P(FemPatch, EnergyIsEnergyDensityTimesVolume) {
  const FemModel model(mesh, {Material::general(elasticity, 1.0)});
  const Eigen::Matrix3d e =
      0.5 * (deformation.transpose() * deformation - Eigen::Matrix3d::Identity());
  const Eigen::Matrix3d stress = deformation.inverse() * first_piola;
  const double expected = 0.5 * stress.cwiseProduct(e).sum();  // unit cube
  EXPECT_LT(std::abs(model.strain_energy(u) - expected) / expected, 1e-14);
}

// Interior forces cancel; the x = 1 face carries P e_x · area (the traction on the side faces'
// strips next to it cancels between opposite faces); all forces sum to zero. Measured, relative
// to |P| · area: interior 1.0e-16, face 4.9e-17, sum 8.9e-17 (tetrahedra); interior 6.9e-17,
// face 2.1e-16, sum 2.7e-16 (hexahedra).
TEST_P(FemPatch, ForcesAreZeroInsideAndTractionOnFaces) {
  const FemModel model(mesh, {Material::general(elasticity, 1.0)});
  Eigen::VectorXd forces;
  model.internal_forces(u, forces);
  const double scale = first_piola.norm();  // × unit face area
  double interior = 0.0;
  Eigen::Vector3d face = Eigen::Vector3d::Zero();
  for (Eigen::Index v = 0; v < mesh.num_vertices(); ++v) {
    if (!on_boundary(mesh.vertices.row(v))) {
      interior = std::max(interior, forces.segment<3>(3 * v).norm());
    }
    if (mesh.vertices(v, 0) == 1.0) face += forces.segment<3>(3 * v);
  }
  EXPECT_LT(interior / scale, 1e-14);
  EXPECT_LT((face - first_piola.col(0)).norm() / scale, 1e-14);
  EXPECT_LT(forces.reshaped(3, mesh.num_vertices()).rowwise().sum().norm() / scale, 1e-14);
}

INSTANTIATE_TEST_SUITE_P(ElementTypes, FemPatch, ::testing::ValuesIn(test::all_element_types),
                         test::element_type_name);

}  // namespace
}  // namespace khz::reduced
