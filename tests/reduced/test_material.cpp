// Materials: Lamé conversion, StVK and general constructors, input checks, and that the FEM
// model applies the Voigt convention as documented.
#include <khz/reduced/errors.hpp>
#include <khz/reduced/fem/element_shape.hpp>
#include <khz/reduced/fem/fem_model.hpp>
#include <khz/reduced/fem/material.hpp>
#include <khz/reduced/meshing/box_mesh.hpp>
#include <khz/test/fixtures.hpp>

#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <limits>
#include <random>

namespace khz::reduced {
namespace {

using test::throws_with_message;

constexpr double nan = std::numeric_limits<double>::quiet_NaN();
constexpr double inf = std::numeric_limits<double>::infinity();

TEST(Material, LameFromYoungPoissonKnownValues) {
  // E = 1, ν = ¼: λ = ¼ / (5/4 · ½) = 0.4, μ = 1 / (2 · 5/4) = 0.4.
  const LameParameters quarter = lame_from_young_poisson(1.0, 0.25);
  EXPECT_DOUBLE_EQ(quarter.lambda, 0.4);
  EXPECT_DOUBLE_EQ(quarter.mu, 0.4);
  // Steel, E = 210 GPa, ν = 0.3: λ = 121.154 GPa, μ = 80.769 GPa.
  const LameParameters steel = lame_from_young_poisson(210e9, 0.3);
  EXPECT_NEAR(steel.lambda, 121.153846153846e9, 1e-3);
  EXPECT_NEAR(steel.mu, 80.7692307692308e9, 1e-3);
  // ν = 0: no lateral coupling, μ = E/2.
  const LameParameters uncoupled = lame_from_young_poisson(3.0, 0.0);
  EXPECT_EQ(uncoupled.lambda, 0.0);
  EXPECT_DOUBLE_EQ(uncoupled.mu, 1.5);
}

TEST(Material, LameFromYoungPoissonRejectsInvalidInput) {
  for (const double young : {0.0, -1.0, nan, inf}) {
    EXPECT_TRUE(throws_with_message<Error>([&] { lame_from_young_poisson(young, 0.3); },
                                           "Young's modulus must be positive and finite"));
  }
  for (const double poisson : {0.5, 0.7, -1.0, -2.0, nan}) {
    EXPECT_TRUE(throws_with_message<Error>([&] { lame_from_young_poisson(1e6, poisson); },
                                           "Poisson ratio must lie in (-1, 0.5)"));
  }
}

TEST(Material, StvkElasticityUsesEngineeringShears) {
  const VoigtMatrix c = stvk_elasticity({2.0, 3.0});
  VoigtMatrix expected = VoigtMatrix::Zero();
  expected.topLeftCorner<3, 3>().setConstant(2.0);
  expected.diagonal() << 8, 8, 8, 3, 3, 3;
  EXPECT_EQ(c, expected);
}

TEST(Material, StvkConstructorsRecordParameters) {
  const Material rubber = Material::stvk(1e6, 0.45, 1100.0);
  EXPECT_TRUE(rubber.is_stvk());
  EXPECT_EQ(rubber.density(), 1100.0);
  const LameParameters lame = lame_from_young_poisson(1e6, 0.45);
  EXPECT_EQ(rubber.lame().lambda, lame.lambda);
  EXPECT_EQ(rubber.lame().mu, lame.mu);
  EXPECT_EQ(rubber.elasticity(), stvk_elasticity(lame));

  const Material negative_lambda = Material::stvk_lame({-1.0, 2.0}, 1.0);  // ν < 0 is allowed
  EXPECT_EQ(negative_lambda.lame().lambda, -1.0);
}

TEST(Material, StvkRejectsInvalidInput) {
  EXPECT_TRUE(throws_with_message<Error>([] { Material::stvk(1e6, 0.3, 0.0); },
                                         "density must be positive and finite"));
  EXPECT_TRUE(throws_with_message<Error>([] { Material::stvk(1e6, 0.3, nan); }, "density"));
  EXPECT_TRUE(throws_with_message<Error>([] { Material::stvk(-5.0, 0.3, 1.0); }, "Young"));
  EXPECT_TRUE(throws_with_message<Error>([] { Material::stvk(1e6, 0.5, 1.0); }, "Poisson"));
  EXPECT_TRUE(throws_with_message<Error>(
      [] {
        Material::stvk_lame({1.0, 0.0}, 1.0);
      },
      "shear modulus mu must be positive"));
  EXPECT_TRUE(throws_with_message<Error>(
      [] {
        Material::stvk_lame({-2.0, 3.0}, 1.0);
      },
      "3·lambda + 2·mu > 0"));
  EXPECT_TRUE(throws_with_message<Error>([] { Material::stvk_lame({nan, 1.0}, 1.0); }, "mu"));
}

TEST(Material, GeneralAcceptsSymmetricPositiveDefiniteMatrix) {
  // An orthotropic material: positive definite, not isotropic.
  VoigtMatrix c = VoigtMatrix::Zero();
  c.topLeftCorner<3, 3>() << 10, 2, 1, 2, 8, 3, 1, 3, 12;
  c.diagonal().tail<3>() << 2, 3, 4;
  const Material material = Material::general(c, 500.0);
  EXPECT_FALSE(material.is_stvk());
  EXPECT_EQ(material.elasticity(), c);
  EXPECT_EQ(material.density(), 500.0);
  EXPECT_EQ(material.lame().mu, 0.0);
  // Asymmetry at round-off level (1e-14 relative) is accepted and removed.
  VoigtMatrix nearly = c;
  nearly(0, 1) += 1e-13;
  EXPECT_EQ(Material::general(nearly, 1.0).elasticity(),
            Material::general(nearly, 1.0).elasticity().transpose());
}

TEST(Material, GeneralRejectsUnsymmetricMatrix) {
  VoigtMatrix c = stvk_elasticity({1.0, 1.0});
  c(0, 4) = 0.1;
  EXPECT_TRUE(throws_with_message<Error>([&] { Material::general(c, 1.0); },
                                         "elasticity matrix is not symmetric"));
}

TEST(Material, GeneralRejectsIndefiniteOrSingularMatrix) {
  VoigtMatrix indefinite = stvk_elasticity({1.0, 1.0});
  indefinite(3, 3) = -0.5;
  EXPECT_TRUE(throws_with_message<Error>([&] { Material::general(indefinite, 1.0); },
                                         "elasticity matrix is not positive definite"));
  // 3λ + 2μ = 0: a volume change costs no energy (singular).
  EXPECT_TRUE(throws_with_message<Error>(
      [&] {
        Material::general(stvk_elasticity({-2.0, 3.0}), 1.0);
      },
      "not positive definite"));
  EXPECT_TRUE(
      throws_with_message<Error>([] { Material::general(VoigtMatrix::Zero(), 1.0); }, "zero"));
  VoigtMatrix non_finite = stvk_elasticity({1.0, 1.0});
  non_finite(2, 2) = nan;
  EXPECT_TRUE(
      throws_with_message<Error>([&] { Material::general(non_finite, 1.0); }, "non-finite"));
  EXPECT_TRUE(throws_with_message<Error>(
      [] {
        Material::general(stvk_elasticity({1.0, 1.0}), -1.0);
      },
      "density"));
}

// The model's internal force on a single tetrahedron against eq. 2.2 written out by hand:
// S = λ tr(E) I + 2μE, P = F S, R_a = V P ∇φ_a. Catches a wrong Voigt shear factor.
// Measured relative differences 8.5e-17 (forces), 1.5e-16 (energy).
TEST(Material, StvkForcesFollowTheTensorFormula) {
  VolumeMesh mesh;
  mesh.vertices.resize(4, 3);
  mesh.vertices << 0.1, 0.0, 0.0, 1.0, 0.2, 0.0, 0.1, 0.9, 0.1, 0.0, 0.3, 1.1;
  mesh.elements.resize(1, 4);
  mesh.elements << 0, 1, 2, 3;
  const LameParameters lame{2.0e5, 1.0e5};
  const FemModel model(mesh, {Material::stvk_lame(lame, 1.0)});
  Eigen::VectorXd u(12);
  u << 0.05, -0.1, 0.2, 0.3, 0.1, -0.2, -0.1, 0.25, 0.05, 0.15, -0.05, 0.3;

  const TetCorners corners = mesh.vertices;
  const Eigen::Matrix<double, 4, 3, Eigen::RowMajor> gradients = tet_shape_gradients(corners);
  Eigen::Matrix3d f = Eigen::Matrix3d::Identity();
  for (int a = 0; a < 4; ++a) f += u.segment<3>(3 * a) * gradients.row(a);
  const Eigen::Matrix3d e = 0.5 * (f.transpose() * f - Eigen::Matrix3d::Identity());
  const Eigen::Matrix3d s = lame.lambda * e.trace() * Eigen::Matrix3d::Identity() + 2 * lame.mu * e;
  const double volume = tet_signed_volume(corners);
  Eigen::VectorXd expected(12);
  for (int a = 0; a < 4; ++a) {
    expected.segment<3>(3 * a) = volume * f * s * gradients.row(a).transpose();
  }
  Eigen::VectorXd forces;
  model.internal_forces(u, forces);
  EXPECT_LT((forces - expected).norm() / expected.norm(), 1e-14);
  const double energy = volume * 0.5 * s.cwiseProduct(e).sum();
  EXPECT_LT(std::abs(model.strain_energy(u) - energy) / energy, 1e-14);
}

// general(stvk_elasticity(λ, μ)) must behave exactly like stvk_lame(λ, μ): the model may not
// treat StVK materials differently. Measured: identical to the last bit.
TEST(Material, GeneralStvkMatrixReproducesStvk) {
  const LameParameters lame = lame_from_young_poisson(5e5, 0.35);
  const VolumeMesh mesh = box_hex_mesh({0, 0, 0}, {1, 0.5, 0.5}, {2, 1, 1});
  const FemModel stvk(mesh, {Material::stvk_lame(lame, 1000.0)});
  const FemModel general(mesh, {Material::general(stvk_elasticity(lame), 1000.0)});
  std::mt19937 random(2);
  std::uniform_real_distribution<double> entry(-0.2, 0.2);
  Eigen::VectorXd u(stvk.num_dofs());
  for (Eigen::Index i = 0; i < u.size(); ++i) u[i] = entry(random);

  EXPECT_LE(std::abs(stvk.strain_energy(u) - general.strain_energy(u)),
            1e-15 * stvk.strain_energy(u));
  Eigen::VectorXd r_stvk, r_general;
  SparseMatrix k_stvk = stvk.stiffness_pattern(), k_general = general.stiffness_pattern();
  stvk.forces_and_stiffness(u, r_stvk, k_stvk);
  general.forces_and_stiffness(u, r_general, k_general);
  EXPECT_LE((r_stvk - r_general).norm(), 1e-15 * r_stvk.norm());
  EXPECT_LE(SparseMatrix(k_stvk - k_general).norm(), 1e-15 * k_stvk.norm());
}

}  // namespace
}  // namespace khz::reduced
