// The modal-derivative basis (thesis §2.8.3, eq. 2.52; free objects §2.8.7) and mass-PCA
// (§2.8.1), checked independently: the eq. 2.52 weighting column by column, the basis against
// the subspace it must span, reduced static solves against full ones under large twists and
// bends (the spirit of thesis Fig. 2.14), and mass-PCA against a dense Gram-matrix reference on
// a graded mesh, where it must beat plain PCA in the mass norm.
#include <khz/reduced/basis/linear_modes.hpp>
#include <khz/reduced/basis/mass_pca.hpp>
#include <khz/reduced/basis/modal_derivative_basis.hpp>
#include <khz/reduced/basis/modal_derivatives.hpp>
#include <khz/reduced/errors.hpp>
#include <khz/reduced/fem/fem_model.hpp>
#include <khz/reduced/meshing/box_mesh.hpp>
#include <khz/test/large_deformation.hpp>

#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <string>
#include <vector>

namespace khz::reduced {
namespace {

const Material rubber = Material::stvk(1e6, 0.3, 1000.0);

double mass_norm(const SparseMatrix& mass, const Eigen::VectorXd& v) {
  return std::sqrt(v.dot(mass * v));
}

/// ‖v − U Uᵀ M v‖_M / ‖v‖_M for an M-orthonormal U.
double projection_residual(const Eigen::MatrixXd& basis, const SparseMatrix& mass,
                           const Eigen::VectorXd& v) {
  return mass_norm(mass, v - basis * (basis.transpose() * (mass * v))) / mass_norm(mass, v);
}

double orthonormality_error(const Eigen::MatrixXd& basis, const SparseMatrix& mass) {
  const Eigen::MatrixXd gram = basis.transpose() * (mass * basis);
  return (gram - Eigen::MatrixXd::Identity(gram.rows(), gram.cols())).cwiseAbs().maxCoeff();
}

/// A 1 × 0.3 × 0.2 bar of 5 × 2 × 2 hexahedra clamped at x = 0 (distinct sides: simple
/// eigenvalues).
struct Bar {
  FemModel model{box_hex_mesh({0, 0, 0}, {1.0, 0.3, 0.2}, {5, 2, 2}), {rubber}};
  std::vector<int> clamped = vertices_in_box(
      model.mesh().vertices,
      Eigen::AlignedBox3d(Eigen::Vector3d(-1e-9, -1, -1), Eigen::Vector3d(1e-9, 1, 1)));
  SparseMatrix mass = model.mass_matrix();
};

LinearModes modes_of(const FemModel& model, std::span<const int> fixed, int k) {
  LinearModesOptions options;
  options.num_modes = k;
  return compute_linear_modes(model, fixed, options);
}

// ---------------------------------------------------------------------------------------------
// Eq. 2.52 weighting.

/// Checks the columns of weighted_modal_samples against eq. 2.52, computed here from the parts.
/// Measured: modes exact, derivatives ≤ 1.3e-16 relative.
void expect_weighted_samples(const LinearModes& modes, const ModalDerivatives& derivatives,
                             const SparseMatrix& mass) {
  const Eigen::MatrixXd samples = weighted_modal_samples(modes, derivatives, mass);
  const Eigen::Index k = modes.eigenvalues.size();
  const auto pairs = static_cast<Eigen::Index>(derivatives.pairs.size());
  ASSERT_EQ(samples.rows(), modes.modes.rows());
  ASSERT_EQ(samples.cols(), k + pairs);
  const Eigen::VectorXd& lambda = modes.eigenvalues;
  for (Eigen::Index j = 0; j < k; ++j) {
    const Eigen::VectorXd expected = lambda[0] / lambda[j] * modes.modes.col(j);
    EXPECT_LT((samples.col(j) - expected).norm(), 1e-12 * expected.norm()) << "mode " << j;
  }
  for (Eigen::Index c = 0; c < pairs; ++c) {
    const auto [i, j] = derivatives.pairs[c];
    const Eigen::VectorXd phi = derivatives.vectors.col(c);
    const Eigen::VectorXd expected =
        lambda[0] * lambda[0] / (lambda[i] * lambda[j]) * phi / mass_norm(mass, phi);
    EXPECT_LT((samples.col(k + c) - expected).norm(), 1e-12 * expected.norm()) << "Φ" << i << j;
  }
}

TEST(WeightedModalSamples, FollowEquation2_52Anchored) {
  const Bar bar;
  const LinearModes modes = modes_of(bar.model, bar.clamped, 3);
  const ModalDerivatives derivatives = compute_modal_derivatives(bar.model, modes);
  expect_weighted_samples(modes, derivatives, bar.mass);
}

// Free object: λ₁ is the first deformation eigenvalue (the rigid ones are not modes), k² pairs.
TEST(WeightedModalSamples, FollowEquation2_52Free) {
  const Bar bar;
  const LinearModes modes = modes_of(bar.model, {}, 3);
  const ModalDerivatives derivatives = compute_modal_derivatives(bar.model, modes);
  ASSERT_EQ(derivatives.pairs.size(), 9u);
  expect_weighted_samples(modes, derivatives, bar.mass);
}

TEST(WeightedModalSamples, RejectsMismatchedSizesAndZeroDerivatives) {
  const Bar bar;
  const LinearModes modes = modes_of(bar.model, bar.clamped, 2);
  const ModalDerivatives derivatives = compute_modal_derivatives(bar.model, modes);
  const FemModel small(box_hex_mesh({0, 0, 0}, {1, 1, 1}, {1, 1, 1}), {rubber});
  EXPECT_THROW(weighted_modal_samples(modes, derivatives, small.mass_matrix()), Error);
  ModalDerivatives zero = derivatives;
  zero.vectors.col(1).setZero();
  EXPECT_THROW(weighted_modal_samples(modes, zero, bar.mass), Error);
  ModalDerivatives short_rows = derivatives;
  short_rows.vectors.conservativeResize(derivatives.vectors.rows() - 3, Eigen::NoChange);
  EXPECT_THROW(weighted_modal_samples(modes, short_rows, bar.mass), Error);
  ModalDerivatives missing_pair = derivatives;
  missing_pair.pairs.pop_back();
  EXPECT_THROW(weighted_modal_samples(modes, missing_pair, bar.mass), Error);
}

// ---------------------------------------------------------------------------------------------
// modal_derivative_basis.

// With r = k + k(k+1)/2 nothing is dropped: the basis spans every mode and derivative.
// Measured: projection residuals ≤ 1.3e-15. The clamped rows are ~1e-16, not exactly zero.
TEST(ModalDerivativeBasis, FullSizeSpansModesAndDerivatives) {
  const Bar bar;
  ModalDerivativeBasisOptions options;
  options.modes.num_modes = 3;
  options.basis_size = 3 + 6;
  const Basis basis = modal_derivative_basis(bar.model, bar.clamped, options);
  ASSERT_EQ(basis.size(), 9);
  ASSERT_EQ(basis.vectors.rows(), bar.model.num_dofs());
  EXPECT_EQ(basis.fixed_vertices, bar.clamped);
  EXPECT_FALSE(basis.recipe.empty());
  EXPECT_LT(orthonormality_error(basis.vectors, bar.mass), 1e-10);
  double at_clamp = 0.0;
  for (int v : bar.clamped) {
    at_clamp = std::max(at_clamp, basis.vectors.middleRows(3 * v, 3).cwiseAbs().maxCoeff());
  }
  EXPECT_EQ(at_clamp, 0.0) << "Basis::vectors promises zero rows at fixed vertices";

  const LinearModes modes = modes_of(bar.model, bar.clamped, 3);
  const ModalDerivatives derivatives = compute_modal_derivatives(bar.model, modes);
  double worst = 0.0;
  for (Eigen::Index c = 0; c < 3; ++c) {
    worst = std::max(worst, projection_residual(basis.vectors, bar.mass, modes.modes.col(c)));
  }
  for (Eigen::Index c = 0; c < derivatives.vectors.cols(); ++c) {
    worst =
        std::max(worst, projection_residual(basis.vectors, bar.mass, derivatives.vectors.col(c)));
  }
  EXPECT_LT(worst, 1e-8);
}

// The one-call pipeline equals its parts: modes → derivatives → eq. 2.52 → mass-PCA (compared
// as subspaces, through their M-orthogonal projectors). Measured: identical (difference 0).
TEST(ModalDerivativeBasis, EqualsThePipelineOfItsParts) {
  const Bar bar;
  ModalDerivativeBasisOptions options;
  options.modes.num_modes = 4;
  options.basis_size = 7;
  const Basis basis = modal_derivative_basis(bar.model, bar.clamped, options);
  const LinearModes modes = modes_of(bar.model, bar.clamped, 4);
  const ModalDerivatives derivatives = compute_modal_derivatives(bar.model, modes);
  PcaOptions pca;
  pca.basis_size = 7;
  const PcaResult manual =
      principal_components(weighted_modal_samples(modes, derivatives, bar.mass), bar.mass, pca);
  const Eigen::MatrixXd p1 = basis.vectors * (basis.vectors.transpose() * bar.mass);
  const Eigen::MatrixXd p2 = manual.basis * (manual.basis.transpose() * bar.mass);
  EXPECT_LT((p1 - p2).norm() / p2.norm(), 1e-8);
}

// Free object: mass-orthonormal, spans the deformation modes, M-orthogonal to the rigid ones.
TEST(ModalDerivativeBasis, FreeObject) {
  const Bar bar;
  ModalDerivativeBasisOptions options;
  options.modes.num_modes = 3;
  options.basis_size = 3 + 9;
  const Basis basis = modal_derivative_basis(bar.model, {}, options);
  ASSERT_EQ(basis.size(), 12);
  EXPECT_TRUE(basis.fixed_vertices.empty());
  EXPECT_LT(orthonormality_error(basis.vectors, bar.mass), 1e-10);
  const LinearModes modes = modes_of(bar.model, {}, 3);
  for (Eigen::Index c = 0; c < 3; ++c) {
    EXPECT_LT(projection_residual(basis.vectors, bar.mass, modes.modes.col(c)), 1e-8);
  }
  // Eq. 2.60's Φᵢⱼ, i ≠ j, have rigid-rotation components (see test_modal_derivatives.cpp;
  // max |RᵀMU| = 0.78 before projection); the basis is projected off the rigid modes.
  EXPECT_LT((modes.rigid_modes.transpose() * (bar.mass * basis.vectors)).cwiseAbs().maxCoeff(),
            1e-10);
}

TEST(ModalDerivativeBasis, RejectsBadSizes) {
  const Bar bar;
  ModalDerivativeBasisOptions options;
  options.modes.num_modes = 2;
  options.basis_size = 2 + 3 + 1;  // more than the samples
  EXPECT_THROW(modal_derivative_basis(bar.model, bar.clamped, options), Error);
  options.basis_size = 0;
  EXPECT_THROW(modal_derivative_basis(bar.model, bar.clamped, options), Error);
}

TEST(ModalDerivativeBasis, ReportsEveryStageAndCancels) {
  const Bar bar;
  std::vector<std::string> stages;
  ModalDerivativeBasisOptions options;
  options.modes.num_modes = 2;
  options.basis_size = 4;
  bool inner_called = false;
  options.modes.progress = [&](const Progress&) { return inner_called = true; };
  options.derivatives.progress = [&](const Progress&) { return inner_called = true; };
  options.progress = [&](const Progress& p) {
    if (stages.empty() || stages.back() != p.stage) stages.emplace_back(p.stage);
    return true;
  };
  modal_derivative_basis(bar.model, bar.clamped, options);
  EXPECT_FALSE(inner_called);
  EXPECT_EQ(stages, (std::vector<std::string>{"linear modes", "Hessian contractions",
                                              "modal derivatives", "mass PCA"}));
  for (const char* stage :
       {"linear modes", "Hessian contractions", "modal derivatives", "mass PCA"}) {
    options.progress = [stage](const Progress& p) { return p.stage != stage; };
    EXPECT_THROW(modal_derivative_basis(bar.model, bar.clamped, options), Cancelled) << stage;
  }
}

// ---------------------------------------------------------------------------------------------
// Large deformations (thesis Fig. 2.14): a 1 × 0.1 × 0.08 beam of n × 2 × 2 hexahedra (n = 8
// here, 20 in benchmarks/bench_basis_large_deformation.cpp), clamped at x = 0, twisted by a
// torque and bent by a tip load. The full nonlinear static solution is the reference; the same
// static problem restricted to u = U q is solved with a small Newton loop, in a modal-derivative
// basis and in a linear-mode basis of the same size. The machinery is shared with the benchmark
// in tests/support/khz/test/large_deformation.hpp.

using test::BasisPair;
using test::Comparison;
using test::degrees;
using test::LargeBeam;

// The light version of the thesis' 270° twist (which, with a 20-cell beam and 27 load steps,
// takes about a minute in a Debug build and lives in benchmarks/bench_basis_large_deformation):
// an 8-cell beam twisted by a 6 N·m follower torque in one load step. Derivative basis:
// span{Ψt1, Ψt2, Φt1t1, Φt1t2, Φt2t2} of the two lowest torsion modes; linear basis: the five
// lowest torsion modes, the best a linear basis of that size can do for a twist.
// Measured (dense-solver modes and derivatives, cross-checked with the library's): full 85.6°;
// derivative basis 74.3°, relative mass-norm error 0.065; linear basis 8.7°, error 0.946. The
// linear basis cannot shorten the radius of a turning fibre (the −(1 − cos θ) r term), so it
// locks. Bounds: derivative error < 0.1 and within 15° of the full twist; linear > 0.8 and
// at least 5× the derivative basis's error.
TEST(ModalDerivativeBasisLargeDeformation, TwistNinetyDegrees) {
  const LargeBeam beam(8);
  const BasisPair bases = test::large_deformation_bases(beam, true);
  ASSERT_EQ(bases.derivative.cols(), 5) << "fewer than 5 torsion modes among the lowest 30";
  const Comparison run = test::compare_solves(beam, test::follower_torque(beam, 6.0), bases, 1);
  EXPECT_EQ(run.failure(), "");
  EXPECT_NEAR(run.full.twist * degrees, 85.6, 2.0);
  EXPECT_LT(run.derivative_error, 0.1);
  EXPECT_NEAR(run.derivative.twist, run.full.twist, 15.0 / degrees);
  EXPECT_GT(run.linear_error, 0.8);
  EXPECT_GT(run.linear_error, 5 * run.derivative_error);
  EXPECT_LT(run.linear.twist * degrees, 20.0);
}

// The light version of the bend: a dead tip load P = 4 EI/L² along −z in one load step bends
// the 8-cell beam's tip by 45° (a dead load approaches 90° only as P → ∞; the benchmark goes to
// PL²/EI = 10, 79°). Derivative basis: span{Ψb1, Ψb2, Φb1b1, Φb1b2, Φb2b2} of the two lowest
// z-bending modes; linear basis: the five lowest z-bending modes.
// Measured: full 44.8°; derivative basis 43.8°, error 0.0032; linear basis 5.9°, error 0.825
// (bending modes cannot shorten the beam axis, so the bent beam would have to stretch).
// Bounds: derivative error < 0.01 and within 3°; linear > 0.5 and at least 20× the derivative
// basis's error.
TEST(ModalDerivativeBasisLargeDeformation, BendFortyFiveDegrees) {
  const LargeBeam beam(8);
  const BasisPair bases = test::large_deformation_bases(beam, false);
  ASSERT_EQ(bases.derivative.cols(), 5) << "fewer than 5 z-bending modes among the lowest 30";
  // A dead load: the reference is the library's solve_static, in one load step.
  const Comparison run = test::compare_solves(beam, test::dead_tip_bend(beam, 4.0), bases, 1);
  EXPECT_EQ(run.failure(), "");
  const double full_bend = test::tip_bend(beam, run.full.displacement);
  EXPECT_NEAR(full_bend * degrees, 44.8, 1.0);
  EXPECT_LT(run.derivative_error, 0.01);
  EXPECT_NEAR(test::tip_bend(beam, run.derivative.displacement), full_bend, 3.0 / degrees);
  EXPECT_GT(run.linear_error, 0.5);
  EXPECT_GT(run.linear_error, 20 * run.derivative_error);
}

// ---------------------------------------------------------------------------------------------
// Mass-PCA.

/// A 1 × 0.25 × 0.25 bar of tetrahedra, 20 × 3 × 3 cells, whose x < ½ half has 16 cells along
/// x and the x > ½ half 4: cells 4× finer on one side, same mass per volume everywhere.
VolumeMesh graded_mesh() {
  VolumeMesh mesh = box_tet_mesh({0, 0, 0}, {20, 0.25, 0.25}, {20, 3, 3});
  for (Eigen::Index v = 0; v < mesh.num_vertices(); ++v) {
    const double i = mesh.vertices(v, 0);  // lattice index along x
    mesh.vertices(v, 0) = i <= 16 ? i / 32.0 : 0.5 + (i - 16) / 8.0;
  }
  return mesh;
}

/// N smooth deformations of the graded bar: random combinations of 12 fields, each a sin² bump
/// over one half of the bar along x, y or z, uniform or with a cos(π·/w) pattern across the
/// section (2 halves × 3 directions × 2 patterns). The coarse half's fields are 1.5× stronger:
/// they carry more mass norm (the halves have equal volumes), while the fine half's carry more
/// Euclidean norm (4× the vertices).
Eigen::MatrixXd smooth_samples(const VolumeMesh& mesh, int count, unsigned seed) {
  std::mt19937 random(seed);
  std::normal_distribution<double> normal;
  const Eigen::Index n = mesh.num_vertices();
  Eigen::MatrixXd fields = Eigen::MatrixXd::Zero(3 * n, 12);
  for (Eigen::Index v = 0; v < n; ++v) {
    const double x = mesh.vertices(v, 0), y = mesh.vertices(v, 1), z = mesh.vertices(v, 2);
    for (int half = 0; half < 2; ++half) {
      const double start = 0.5 * half;
      if (x < start || x > start + 0.5) continue;
      const double bump = std::pow(std::sin(2 * std::numbers::pi * (x - start)), 2);
      const double strength = half == 1 ? 1.5 : 1.0;
      for (int axis = 0; axis < 3; ++axis) {
        const double pattern[2] = {1.0, std::cos(std::numbers::pi * (axis == 2 ? y : z) / 0.25)};
        for (int p = 0; p < 2; ++p) {
          fields(3 * v + axis, 6 * half + 2 * axis + p) =
              strength * (1.0 - 0.1 * axis - 0.3 * p) * bump * pattern[p];
        }
      }
    }
  }
  Eigen::MatrixXd coefficients(12, count);
  for (Eigen::Index i = 0; i < coefficients.size(); ++i) coefficients(i) = normal(random);
  return fields * coefficients;
}

class MassPcaGraded : public ::testing::Test {
 protected:
  FemModel model{graded_mesh(), {rubber}};
  SparseMatrix mass = model.mass_matrix();
  Eigen::MatrixXd samples = smooth_samples(model.mesh(), 40, 7);  // rank 12

  /// Σ ‖u − P u‖²_M with P the M-orthogonal projector onto span(U): U(UᵀMU)⁻¹UᵀM.
  double mass_error(const Eigen::MatrixXd& basis) const {
    const Eigen::MatrixXd gram = basis.transpose() * (mass * basis);
    const Eigen::MatrixXd coefficients = gram.ldlt().solve(basis.transpose() * (mass * samples));
    const Eigen::MatrixXd rest = samples - basis * coefficients;
    return (rest.transpose() * (mass * rest)).trace();
  }
};

// Mass-PCA is the optimal r-subspace in the mass norm; plain PCA, favouring the finely meshed
// half, picks other directions. Measured at r = 6: Σ‖u − Pu‖²_M = 533.9 (mass-PCA) vs 713.3
// (plain PCA), ratio 0.749.
TEST_F(MassPcaGraded, BeatsPlainPcaInTheMassNorm) {
  PcaOptions options;
  options.basis_size = 6;
  const PcaResult by_mass = principal_components(samples, mass, options);
  options.metric = PcaMetric::euclidean;
  const PcaResult plain = principal_components(samples, mass, options);
  const double mass_pca_error = mass_error(by_mass.basis);
  const double plain_error = mass_error(plain.basis);
  EXPECT_LT(mass_pca_error, 0.85 * plain_error);
  // The optimal error is the tail Σ_{i>r} σᵢ².
  EXPECT_NEAR(mass_pca_error, by_mass.singular_values.tail(40 - 6).squaredNorm(),
              1e-10 * by_mass.singular_values.squaredNorm());
  // Plain PCA is orthonormal and optimal in its own (Euclidean) norm.
  EXPECT_LT((plain.basis.transpose() * plain.basis - Eigen::MatrixXd::Identity(6, 6))
                .cwiseAbs()
                .maxCoeff(),
            1e-12);
  const Eigen::MatrixXd plain_rest = samples - plain.basis * (plain.basis.transpose() * samples);
  EXPECT_NEAR(plain_rest.squaredNorm(), plain.singular_values.tail(40 - 6).squaredNorm(),
              1e-10 * plain.singular_values.squaredNorm());
}

/// Singular values and leading M-orthonormal directions from the N × N Gram matrix XᵀMX =
/// V Σ² Vᵀ: U = X V Σ⁻¹.
struct GramReference {
  Eigen::VectorXd singular_values;  ///< Descending.
  Eigen::MatrixXd basis;            ///< First r columns.
};

GramReference gram_reference(const Eigen::MatrixXd& samples, const SparseMatrix& metric, int r) {
  const Eigen::MatrixXd gram = samples.transpose() * (metric * samples);
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> solver(gram);
  const Eigen::Index n = gram.rows();
  GramReference reference;
  reference.singular_values = solver.eigenvalues().reverse().cwiseMax(0.0).cwiseSqrt();
  reference.basis.resize(samples.rows(), r);
  for (int c = 0; c < r; ++c) {
    reference.basis.col(c) =
        samples * solver.eigenvectors().col(n - 1 - c) / reference.singular_values[c];
  }
  return reference;
}

/// Checks a PCA result against the Gram reference in `metric` (singular values to 1e-10 σ₁,
/// directions up to sign, the sign convention: largest-magnitude entry positive). Measured:
/// singular values 2.6e-15 σ₁ (the zero tail 1.8e-15 σ₁), directions ≤ 6.8e-15, UᵀMU − I
/// ≤ 2.2e-15.
void expect_matches_gram(const PcaResult& result, const Eigen::MatrixXd& samples,
                         const SparseMatrix& metric, int r) {
  const GramReference reference = gram_reference(samples, metric, r);
  ASSERT_EQ(result.singular_values.size(), samples.cols());
  ASSERT_EQ(result.basis.cols(), r);
  // The samples have rank 12: those singular values agree to round-off. The Gram matrix
  // squares the singular values, so its reference for the zero tail is only √ε σ₁ ~ 1e-8 σ₁.
  const double sigma1 = reference.singular_values[0];
  EXPECT_LT((result.singular_values - reference.singular_values).head(12).cwiseAbs().maxCoeff(),
            1e-10 * sigma1);
  EXPECT_LT(result.singular_values.tail(samples.cols() - 12).cwiseAbs().maxCoeff(), 1e-7 * sigma1);
  for (Eigen::Index i = 1; i < result.singular_values.size(); ++i) {
    EXPECT_GE(result.singular_values[i - 1], result.singular_values[i]);
  }
  EXPECT_LT(orthonormality_error(result.basis, metric), 1e-10);
  for (int c = 0; c < r; ++c) {
    const Eigen::VectorXd u = result.basis.col(c);
    Eigen::Index largest;
    u.cwiseAbs().maxCoeff(&largest);
    EXPECT_GT(u[largest], 0.0) << "column " << c;
    const double sign = u.dot(metric * reference.basis.col(c)) >= 0 ? 1.0 : -1.0;
    EXPECT_LT(mass_norm(metric, u - sign * reference.basis.col(c)), 1e-8) << "column " << c;
  }
}

TEST_F(MassPcaGraded, MatchesDenseGramReference) {
  PcaOptions options;
  options.basis_size = 6;
  expect_matches_gram(principal_components(samples, mass, options), samples, mass, 6);
}

TEST_F(MassPcaGraded, LumpedMetricUsesRowSums) {
  // Row-sum lumping of the given (consistent) matrix, built here independently.
  const Eigen::VectorXd row_sums = Eigen::MatrixXd(mass).rowwise().sum();
  const SparseMatrix lumped = SparseMatrix(row_sums.asDiagonal());
  PcaOptions options;
  options.basis_size = 6;
  options.metric = PcaMetric::lumped_mass;
  expect_matches_gram(principal_components(samples, mass, options), samples, lumped, 6);
}

TEST_F(MassPcaGraded, RejectsBadInput) {
  PcaOptions options;
  options.basis_size = 41;  // more than the 40 samples
  EXPECT_THROW(principal_components(samples, mass, options), Error);
  options.basis_size = 0;
  EXPECT_THROW(principal_components(samples, mass, options), Error);
  options.basis_size = 13;  // the samples have rank 12
  EXPECT_THROW(principal_components(samples, mass, options), Error);
  options.basis_size = 4;
  EXPECT_THROW(principal_components(samples.topRows(samples.rows() - 3), mass, options), Error);
  for (double bad :
       {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()}) {
    Eigen::MatrixXd broken = samples;
    broken(5, 3) = bad;
    EXPECT_THROW(principal_components(broken, mass, options), Error);
  }
  const SparseMatrix negative = -mass;
  try {
    principal_components(samples, negative, options);
    ADD_FAILURE() << "negative definite mass accepted";
  } catch (const SolverError&) {
  } catch (const std::exception& error) {
    ADD_FAILURE() << "wrong exception for a negative definite mass: " << error.what();
  }
  options.progress = [](const Progress&) { return false; };
  EXPECT_THROW(principal_components(samples, mass, options), Cancelled);
}

}  // namespace
}  // namespace khz::reduced
