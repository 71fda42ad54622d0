// Rigid motions (translations, 90° and 180° rotations, a random rotation) of a free body must
// store no strain energy and produce no internal forces, however large the displacement.
#include <khz/reduced/fem/fem_model.hpp>
#include <khz/reduced/meshing/box_mesh.hpp>

#include <khz/test/element_types.hpp>

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <vector>

namespace khz::reduced {
namespace {

/// A 2×2×2 box of the given type with vertices moved randomly (general element shapes) and an
/// anisotropic material (all of C in play).
FemModel distorted_model(ElementType type) {
  const Eigen::Vector3d min_corner(0, 0, 0), max_corner(1, 1, 1);
  VolumeMesh mesh = type == ElementType::tetrahedron
                        ? box_tet_mesh(min_corner, max_corner, {2, 2, 2})
                        : box_hex_mesh(min_corner, max_corner, {2, 2, 2});
  std::mt19937 random(3);
  std::uniform_real_distribution<double> jitter(-0.07, 0.07);
  for (Eigen::Index i = 0; i < mesh.vertices.size(); ++i) mesh.vertices(i) += jitter(random);
  VoigtMatrix c = stvk_elasticity(lame_from_young_poisson(1e6, 0.4));
  c(0, 3) = c(3, 0) = 1e5;
  c(1, 5) = c(5, 1) = -5e4;
  return FemModel(std::move(mesh), {Material::general(c, 1000.0)});
}

Eigen::VectorXd affine_displacement(const VolumeMesh& mesh, const Eigen::Matrix3d& map,
                                    const Eigen::Vector3d& translation) {
  Eigen::VectorXd u(3 * mesh.num_vertices());
  for (Eigen::Index v = 0; v < mesh.num_vertices(); ++v) {
    u.segment<3>(3 * v) =
        (map - Eigen::Matrix3d::Identity()) * mesh.vertices.row(v).transpose() + translation;
  }
  return u;
}

class FemRigidMotion : public ::testing::TestWithParam<ElementType> {};

// Scales: energy and forces of a 10% uniaxial stretch. Measured worst over all motions below,
// relative to these scales: energy 6.3e-28 / 5.0e-28, forces 2.7e-14 / 1.3e-14 (tetrahedra /
// hexahedra). The force residue is round-off in F = I + Σ u_a ⊗ ∇φ_a with |u| ≈ 8 m
// (translation) against 0.5 m elements.
TEST_P(FemRigidMotion, StoresNoEnergyAndProducesNoForce) {
  const FemModel model = distorted_model(GetParam());
  const VolumeMesh& mesh = model.mesh();
  Eigen::VectorXd forces;
  const Eigen::VectorXd stretch =
      affine_displacement(mesh, Eigen::Vector3d(1.1, 1, 1).asDiagonal(), Eigen::Vector3d::Zero());
  const double energy_scale = model.strain_energy(stretch);
  model.internal_forces(stretch, forces);
  const double force_scale = forces.norm();

  constexpr double pi = std::numbers::pi;
  std::vector<Eigen::Matrix3d> rotations;
  for (const Eigen::Vector3d& axis :
       {Eigen::Vector3d::UnitX().eval(), Eigen::Vector3d::UnitY().eval(),
        Eigen::Vector3d::UnitZ().eval(), Eigen::Vector3d(1, 1, 1).normalized().eval()}) {
    rotations.push_back(Eigen::AngleAxisd(pi / 2, axis).toRotationMatrix());
    rotations.push_back(Eigen::AngleAxisd(pi, axis).toRotationMatrix());
  }
  rotations.push_back(Eigen::Quaterniond(0.3, -0.5, 0.7, 0.2).normalized().toRotationMatrix());
  const Eigen::Vector3d translation(3.0, -2.0, 7.5);

  double worst_energy = 0.0, worst_force = 0.0;
  for (const Eigen::Matrix3d& rotation : rotations) {
    for (const Eigen::Vector3d& shift : {Eigen::Vector3d::Zero().eval(), translation}) {
      const Eigen::VectorXd u = affine_displacement(mesh, rotation, shift);
      worst_energy = std::max(worst_energy, std::abs(model.strain_energy(u)) / energy_scale);
      model.internal_forces(u, forces);
      worst_force = std::max(worst_force, forces.norm() / force_scale);
    }
  }
  EXPECT_LT(worst_energy, 1e-26);
  EXPECT_LT(worst_force, 3e-13);
}

INSTANTIATE_TEST_SUITE_P(ElementTypes, FemRigidMotion, ::testing::ValuesIn(test::all_element_types),
                         test::element_type_name);

}  // namespace
}  // namespace khz::reduced
