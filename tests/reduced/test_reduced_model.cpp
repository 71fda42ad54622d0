#include <khz/reduced/errors.hpp>
#include <khz/reduced/meshing/box_mesh.hpp>
#include <khz/reduced/subspace/projected_forces.hpp>
#include <khz/reduced/subspace/reduced_model.hpp>
#include <khz/test/fixtures.hpp>
#include <khz/test/polynomial_reference.hpp>
#include <khz/test/two_material_box.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

namespace khz::reduced {
namespace {

using test::reference_derivatives;

using test::TwoMaterialBox;

double relative(const Eigen::MatrixXd& value, const Eigen::MatrixXd& reference) {
  return (value - reference).norm() / reference.norm();
}

// Polynomial vs direct projection UᵀR(Uq), UᵀK(Uq)U at small and large deformations
// (|u| up to ~0.5 on a 1 m box: stretches and rotations far into the nonlinear range).
void expect_matches_projection(bool hexahedra) {
  const TwoMaterialBox box(hexahedra, 7);
  const ReducedModel reduced = ReducedModel::precompute(box.model, box.basis);
  const EnergyPolynomial polynomial = reduced.energy_polynomial();
  ProjectedForces projected(box.model, box.basis.vectors);
  std::mt19937 random(3);
  std::normal_distribution<double> entry(0.0, 1.0);
  for (const double scale : {0.01, 0.3, 1.0, 3.0}) {
    Eigen::VectorXd q(7);
    for (Eigen::Index i = 0; i < q.size(); ++i) q[i] = scale * entry(random);
    Eigen::VectorXd forces(7), expected_forces(7);
    Eigen::MatrixXd stiffness(7, 7), expected_stiffness(7, 7);
    reference_derivatives(polynomial, q, forces, stiffness);
    projected.evaluate(q, expected_forces, expected_stiffness);
    SCOPED_TRACE("scale " + std::to_string(scale) + ", max |u| " +
                 std::to_string((box.basis.vectors * q).cwiseAbs().maxCoeff()));
    EXPECT_LT(relative(forces, expected_forces), 1e-10);
    EXPECT_LT(relative(stiffness, expected_stiffness), 1e-10);
    EXPECT_NEAR(polynomial.energy(q), projected.energy(q), 1e-10 * projected.energy(q));
  }
}

TEST(ReducedModel, TetrahedraPolynomialsEqualDirectProjection) { expect_matches_projection(false); }

TEST(ReducedModel, HexahedraPolynomialsEqualDirectProjection) { expect_matches_projection(true); }

TEST(ReducedModel, ReducedMassIsUTransposeMU) {
  const TwoMaterialBox box(false, 5);
  const ReducedModel reduced = ReducedModel::precompute(box.model, box.basis);
  const Eigen::MatrixXd expected =
      box.basis.vectors.transpose() * (box.model.mass_matrix() * box.basis.vectors);
  EXPECT_LT(relative(reduced.mass(), expected), 1e-13);
}

TEST(ReducedModel, RuntimeMaterialChangeEqualsFreshPrecompute) {
  TwoMaterialBox original(false, 5);
  ReducedModel reduced = ReducedModel::precompute(original.model, original.basis);
  reduced.set_lame(0, {9e5, 1e5});
  reduced.set_elasticity_scale(1, 2.5);
  reduced.set_density(0, 3000.0);
  reduced.set_density(1, 700.0);

  const VolumeMesh mesh = TwoMaterialBox::mesh(false);
  const FemModel changed(
      mesh, {Material::stvk_lame({9e5, 1e5}, 3000.0),
             Material::general(2.5 * TwoMaterialBox::anisotropic_elasticity(), 700.0)});
  const ReducedModel fresh = ReducedModel::precompute(changed, original.basis);
  const EnergyPolynomial a = reduced.energy_polynomial(), b = fresh.energy_polynomial();
  EXPECT_LT(relative(a.quadratic, b.quadratic), 1e-13);
  EXPECT_LT(relative(a.cubic, b.cubic), 1e-13);
  EXPECT_LT(relative(a.quartic, b.quartic), 1e-13);
  EXPECT_LT(relative(reduced.mass(), fresh.mass()), 1e-13);
}

TEST(ReducedModel, TruncationEqualsPrecomputeOnTheLeadingVectors) {
  const TwoMaterialBox box(true, 6);
  const ReducedModel reduced = ReducedModel::precompute(box.model, box.basis);
  Basis leading = box.basis;
  leading.vectors = box.basis.vectors.leftCols(4);
  const ReducedModel expected = ReducedModel::precompute(box.model, leading);
  const ReducedModel truncated = reduced.truncated(4);
  ASSERT_EQ(truncated.dimension(), 4);
  const EnergyPolynomial a = truncated.energy_polynomial(), b = expected.energy_polynomial();
  EXPECT_LT(relative(a.quadratic, b.quadratic), 1e-13);
  EXPECT_LT(relative(a.cubic, b.cubic), 1e-13);
  EXPECT_LT(relative(a.quartic, b.quartic), 1e-13);
  EXPECT_LT(relative(truncated.mass(), expected.mass()), 1e-13);
  EXPECT_THROW((void)reduced.truncated(0), Error);
  EXPECT_THROW((void)reduced.truncated(7), Error);
}

TEST(ReducedModel, RejectsBadBasesAndMaterialCalls) {
  TwoMaterialBox box(false, 3);
  Basis wrong = box.basis;
  wrong.vectors.conservativeResize(wrong.vectors.rows() - 3, Eigen::NoChange);
  EXPECT_TRUE(test::throws_with_message<Error>(
      [&] { (void)ReducedModel::precompute(box.model, wrong); }, "rows"));
  Basis nan = box.basis;
  nan.vectors(5, 1) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_TRUE(test::throws_with_message<Error>(
      [&] { (void)ReducedModel::precompute(box.model, nan); }, "non-finite"));

  ReducedModel reduced = ReducedModel::precompute(box.model, box.basis);
  EXPECT_TRUE(test::throws_with_message<Error>(
      [&] {
        reduced.set_lame(1, {1e5, 1e5});
      },
      "general material"));
  EXPECT_TRUE(
      test::throws_with_message<Error>([&] { reduced.set_elasticity_scale(0, 2.0); }, "StVK"));
  EXPECT_TRUE(
      test::throws_with_message<Error>([&] { reduced.set_density(2, 1.0); }, "no material group"));
  EXPECT_TRUE(test::throws_with_message<Error>([&] { reduced.set_density(0, -1.0); }, "positive"));
}

TEST(ReducedModel, IntegratorDefaultsAreValidatedAsNewmarkOptions) {
  const TwoMaterialBox box(false, 3);
  ReducedModel reduced = ReducedModel::precompute(box.model, box.basis);
  ReducedIntegratorDefaults defaults;
  defaults.newmark.time_step = 2e-4;
  defaults.newmark.mass_damping = 0.5;
  defaults.max_newton_iterations = 4;
  defaults.newton_tolerance = 1e-7;
  reduced.set_defaults(defaults);
  const ReducedNewmarkOptions options = reduced.defaults().newmark_options();
  EXPECT_EQ(options.newmark.time_step, 2e-4);
  EXPECT_EQ(options.newmark.mass_damping, 0.5);
  EXPECT_EQ(options.max_newton_iterations, 4);
  EXPECT_EQ(options.tolerance, 1e-7);
  EXPECT_TRUE(std::isinf(options.acceleration_limit));

  ReducedIntegratorDefaults bad = defaults;
  bad.max_newton_iterations = 0;
  EXPECT_TRUE(test::throws_with_message<Error>([&] { reduced.set_defaults(bad); },
                                               "max_newton_iterations"));
  bad = defaults;
  bad.newton_tolerance = std::numeric_limits<double>::infinity();
  EXPECT_TRUE(test::throws_with_message<Error>([&] { reduced.set_defaults(bad); }, "tolerance"));
  bad = defaults;
  bad.newmark.beta = 0.0;  // explicit: not for the implicit integrator the defaults are for
  EXPECT_THROW(reduced.set_defaults(bad), Error);
  EXPECT_EQ(reduced.defaults().max_newton_iterations, 4);  // unchanged by the failures
}

TEST(ReducedModel, ProgressCanCancel) {
  const TwoMaterialBox box(false, 3);
  ReducedModelOptions options;
  int reports = 0;
  options.progress = [&](const Progress& progress) {
    EXPECT_EQ(progress.stage, "reduced polynomials");
    return ++reports < 2;
  };
  EXPECT_THROW((void)ReducedModel::precompute(box.model, box.basis, options), Cancelled);
}

}  // namespace
}  // namespace khz::reduced
