// Modal derivatives (thesis §2.8.3–2.8.4, §2.8.7), checked independently of the solver's own
// linear algebra: anchored objects against a dense solve of eq. 2.47 and against second
// derivatives of nonlinear static solutions (eq. 2.53–2.56); free objects against a dense
// bordered solve of eq. 2.60 and against finite differences of the tangent modes (eq. 2.45).
#include <khz/reduced/basis/linear_modes.hpp>
#include <khz/reduced/basis/modal_derivatives.hpp>
#include <khz/reduced/errors.hpp>
#include <khz/reduced/fem/fem_model.hpp>
#include <khz/reduced/meshing/box_mesh.hpp>
#include <khz/reduced/solvers/fixed_dofs.hpp>
#include <khz/reduced/solvers/static_solver.hpp>

#include <khz/test/element_types.hpp>

#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <algorithm>
#include <array>
#include <cmath>
#include <set>
#include <string>
#include <vector>

namespace khz::reduced {
namespace {

const Material rubber = Material::stvk(1e6, 0.3, 1000.0);

/// A 1 × 0.3 × 0.2 bar (distinct sides: simple eigenvalues), 5 × 2 × 2 cells: 54 vertices.
VolumeMesh bar(ElementType type) {
  const Eigen::Vector3d min_corner(0, 0, 0), max_corner(1.0, 0.3, 0.2);
  const Eigen::Vector3i cells(5, 2, 2);
  return type == ElementType::tetrahedron ? box_tet_mesh(min_corner, max_corner, cells)
                                          : box_hex_mesh(min_corner, max_corner, cells);
}

std::vector<int> clamped_end(const VolumeMesh& mesh) {
  return vertices_in_box(mesh.vertices, Eigen::AlignedBox3d(Eigen::Vector3d(-1e-9, -1, -1),
                                                            Eigen::Vector3d(1e-9, 1, 1)));
}

LinearModes modes_of(const FemModel& model, std::span<const int> fixed, int k) {
  LinearModesOptions options;
  options.num_modes = k;
  return compute_linear_modes(model, fixed, options);
}

double mass_norm(const SparseMatrix& mass, const Eigen::VectorXd& v) {
  return std::sqrt(v.dot(mass * v));
}

double relative_error(const Eigen::VectorXd& value, const Eigen::VectorXd& reference) {
  return (value - reference).norm() / reference.norm();
}

/// Column of pair (i, j), or −1.
Eigen::Index column_of(const ModalDerivatives& derivatives, int i, int j) {
  for (std::size_t c = 0; c < derivatives.pairs.size(); ++c) {
    if (derivatives.pairs[c] == std::array<int, 2>{i, j}) return static_cast<Eigen::Index>(c);
  }
  return -1;
}

/// (H : Ψⱼ) Ψᵢ on the full dofs.
Eigen::VectorXd hessian_term(const FemModel& model, const LinearModes& modes, int i, int j) {
  return model.hessian_contraction(modes.modes.col(j)) * modes.modes.col(i);
}

// ---------------------------------------------------------------------------------------------
// Anchored objects: K Φᵢⱼ = −(H : Ψⱼ) Ψᵢ (eq. 2.47).

class AnchoredDerivatives : public ::testing::TestWithParam<ElementType> {
 protected:
  FemModel model{bar(GetParam()), {rubber}};
  std::vector<int> clamped = clamped_end(model.mesh());
  LinearModes modes = modes_of(model, clamped, 4);
};

// Dense LLᵀ of K on the free dofs (135 of them). Measured worst relative errors 2.2e-13
// (tetrahedra), 1.7e-13 (hexahedra).
TEST_P(AnchoredDerivatives, MatchDenseSolveOfEquation2_47) {
  const ModalDerivatives derivatives = compute_modal_derivatives(model, modes);
  const int k = 4;
  ASSERT_EQ(derivatives.pairs.size(), static_cast<std::size_t>(k * (k + 1) / 2));
  ASSERT_EQ(derivatives.vectors.rows(), model.num_dofs());
  ASSERT_EQ(derivatives.vectors.cols(), k * (k + 1) / 2);
  EXPECT_EQ(derivatives.max_minres_iterations, 0);
  // Every i ≤ j exactly once.
  std::set<std::array<int, 2>> seen(derivatives.pairs.begin(), derivatives.pairs.end());
  EXPECT_EQ(seen.size(), derivatives.pairs.size());
  for (const auto& [i, j] : derivatives.pairs) {
    EXPECT_LE(i, j);
    EXPECT_GE(i, 0);
    EXPECT_LT(j, k);
  }

  const FixedDofs dofs(model.mesh().num_vertices(), clamped);
  SparseMatrix stiffness = model.stiffness_pattern();
  model.tangent_stiffness(Eigen::VectorXd::Zero(model.num_dofs()), stiffness);
  const Eigen::LLT<Eigen::MatrixXd> factor(Eigen::MatrixXd(dofs.restrict_matrix(stiffness)));
  ASSERT_EQ(factor.info(), Eigen::Success);
  for (int i = 0; i < k; ++i) {
    for (int j = i; j < k; ++j) {
      const Eigen::Index c = column_of(derivatives, i, j);
      ASSERT_GE(c, 0) << "pair " << i << "," << j << " missing";
      Eigen::VectorXd reference;
      dofs.expand_vector(factor.solve(-dofs.restrict_vector(hessian_term(model, modes, i, j))),
                         reference);
      EXPECT_LT(relative_error(derivatives.vectors.col(c), reference), 1e-8) << "Φ" << i << j;
    }
  }
  for (int v : clamped) {
    EXPECT_EQ(derivatives.vectors.middleRows(3 * v, 3).cwiseAbs().maxCoeff(), 0.0);
  }
}

// H is the third derivative of the strain energy, symmetric in all three indices, so
// (H : Ψⱼ) Ψᵢ = (H : Ψᵢ) Ψⱼ and eq. 2.47 gives Φᵢⱼ = Φⱼᵢ: storing i ≤ j loses nothing.
// Measured relative asymmetry ≤ 5.3e-15.
TEST_P(AnchoredDerivatives, RightHandSideIsSymmetricInThePair) {
  for (int i = 0; i < 4; ++i) {
    for (int j = i + 1; j < 4; ++j) {
      EXPECT_LT(relative_error(hessian_term(model, modes, i, j), hessian_term(model, modes, j, i)),
                1e-12);
    }
  }
}

// Blocks of right-hand sides are an implementation detail: 1, 3 and 64 columns per block give
// the same derivatives (10 pairs: 3 leaves a remainder block). Measured: ≤ 2.8e-16.
TEST_P(AnchoredDerivatives, BlockSizeDoesNotChangeTheResult) {
  const ModalDerivatives reference = compute_modal_derivatives(model, modes);
  for (int block : {1, 3}) {
    ModalDerivativesOptions options;
    options.block_size = block;
    const ModalDerivatives blocked = compute_modal_derivatives(model, modes, options);
    ASSERT_EQ(blocked.pairs, reference.pairs);
    EXPECT_LT((blocked.vectors - reference.vectors).norm(), 1e-12 * reference.vectors.norm());
  }
}

INSTANTIATE_TEST_SUITE_P(ElementTypes, AnchoredDerivatives,
                         ::testing::ValuesIn(test::all_element_types), test::element_type_name);

/// Static interpretation (§2.8.4): u(p) solves R(u) = M Ψ Λ p (eq. 2.53), u(0) = 0, ∂u/∂p = Ψ
/// and ∂²u/∂pᵢ∂pⱼ = Φᵢⱼ (eq. 2.55). Second-order central differences, exact for the quadratic
/// term and blind to the odd ones (u(−p) = −u(p) + quadratic terms):
///   i ≠ j: [u(h(eᵢ+eⱼ)) − u(h(eᵢ−eⱼ)) − u(h(−eᵢ+eⱼ)) + u(−h(eᵢ+eⱼ))] / 4h²
///   i = j: [u(h eᵢ) − 2 u(0) + u(−h eᵢ)] / h²
/// with error O(h²) from the quartic term of eq. 2.56.
class StaticInterpretation {
 public:
  StaticInterpretation(const FemModel& model, std::span<const int> fixed, const LinearModes& modes)
      : m_model(model),
        m_fixed(fixed.begin(), fixed.end()),
        m_modes(modes),
        m_mass(model.mass_matrix()) {}

  Eigen::VectorXd displacement(const Eigen::VectorXd& p) const {
    const Eigen::VectorXd force = m_mass * (m_modes.modes * m_modes.eigenvalues.cwiseProduct(p));
    // Converged to round-off: ~1e-12 is the floor here, 1e-10 is safely above it. No line
    // search: it only slows Newton down on this problem (backtracking on ‖R − f‖).
    StaticSolveOptions options;
    options.tolerance = 1e-10;
    options.line_search = false;
    return solve_static(m_model, m_fixed, force, options).displacement;
  }

  Eigen::VectorXd second_difference(int i, int j, double h) const {
    const Eigen::Index k = m_modes.eigenvalues.size();
    const Eigen::VectorXd ei = Eigen::VectorXd::Unit(k, i), ej = Eigen::VectorXd::Unit(k, j);
    if (i == j) return (displacement(h * ei) + displacement(-h * ei)) / (h * h);
    return (displacement(h * (ei + ej)) - displacement(h * (ei - ej)) -
            displacement(h * (ej - ei)) + displacement(-h * (ei + ej))) /
           (4 * h * h);
  }

 private:
  const FemModel& m_model;
  std::vector<int> m_fixed;
  const LinearModes& m_modes;
  SparseMatrix m_mass;
};

// The step is set by the displacement it causes: h·max|Ψ| = 1e-2 of the bar's length (a 1 cm
// deflection of a 1 m bar). Measured relative errors of the differences, h then h/2 (ratio):
//   Φ00 5.5e-5, 1.4e-5 (4.00)   Φ01 1.4e-4, 3.4e-5 (4.00)   Φ02 1.9e-3, 4.8e-4 (3.99)
//   Φ11 3.6e-5, 9.1e-6 (4.00)   Φ12 1.7e-3, 4.4e-4 (3.99)   Φ22 1.8e-3, 4.4e-4 (3.99)
// and of the Richardson extrapolation (4 D(h/2) − D(h)) / 3, O(h⁴): ≤ 1.3e-6.
TEST(AnchoredDerivativesStatic, AreSecondDerivativesOfStaticSolutions) {
  const FemModel model(bar(ElementType::tetrahedron), {rubber});
  const std::vector<int> clamped = clamped_end(model.mesh());
  const LinearModes modes = modes_of(model, clamped, 3);
  const ModalDerivatives derivatives = compute_modal_derivatives(model, modes);
  const StaticInterpretation statics(model, clamped, modes);
  const double h = 1e-2 / modes.modes.cwiseAbs().maxCoeff();
  // 20 static solves for three pairs (all six measured above; these include the worst).
  for (const auto& [i, j] : {std::array<int, 2>{0, 0}, {0, 2}, {1, 2}}) {
    const Eigen::VectorXd phi = derivatives.vectors.col(column_of(derivatives, i, j));
    const Eigen::VectorXd coarse_difference = statics.second_difference(i, j, h);
    const Eigen::VectorXd fine_difference = statics.second_difference(i, j, h / 2);
    const double coarse = relative_error(coarse_difference, phi);
    const double fine = relative_error(fine_difference, phi);
    const double extrapolated = relative_error((4 * fine_difference - coarse_difference) / 3, phi);
    EXPECT_LT(extrapolated, 1e-5) << "Φ" << i << j;
    EXPECT_LT(fine, 1e-3) << "Φ" << i << j;
    EXPECT_GT(coarse / fine, 3.0) << "Φ" << i << j << ": not O(h²)";
  }
}

// ---------------------------------------------------------------------------------------------
// Free objects: (K − λᵢM) Φᵢⱼ = (MΨᵢΨᵢᵀ − I)(H : Ψⱼ)Ψᵢ with Ψᵢᵀ M Φᵢⱼ = 0 (eq. 2.60).

class FreeDerivatives : public ::testing::Test {
 protected:
  // 1 × 0.55 × 0.3 box, 4 × 3 × 2 hexahedra: 180 dofs, simple eigenvalues.
  FemModel model{box_hex_mesh({0, 0, 0}, {1.0, 0.55, 0.3}, {4, 3, 2}), {rubber}};
  LinearModes modes = modes_of(model, {}, 3);
  SparseMatrix mass = model.mass_matrix();
  Eigen::MatrixXd dense_mass = Eigen::MatrixXd(mass);

  Eigen::MatrixXd dense_stiffness(const Eigen::VectorXd& u) const {
    SparseMatrix k = model.stiffness_pattern();
    model.tangent_stiffness(u, k);
    return Eigen::MatrixXd(k);
  }
};

// The bordered system [[K − λᵢM, MΨᵢ], [ΨᵢᵀM, 0]] [Φ; μ] = [b; 0] is nonsingular (the kernel
// of K − λᵢM is Ψᵢ, which the border removes), its solution has Ψᵢᵀ M Φ = 0 and μ = 0 since
// b ⊥ Ψᵢ. Dense LU. Measured with the default MINRES tolerance (1e-10, 8 iterations): worst
// relative error 5.3e-11, |Ψᵢᵀ M Φᵢⱼ| / ‖Φᵢⱼ‖_M ≤ 1.4e-17, ‖Φ01 − Φ10‖ / ‖Φ10‖ = 0.061.
// The off-diagonal Φᵢⱼ are partly rigid rotations (measured up to 53 % of ‖Φ02‖_M; Φᵢᵢ: 1e-11),
// and must be: for r = ω × (X − c) multiply eq. 2.60 by rᵀ. K r = 0 and rᵀMΨᵢ = 0 leave
// −λᵢ rᵀMΦᵢⱼ = −rᵀ(H : Ψⱼ)Ψᵢ = −Ψᵢᵀ(H : r)Ψⱼ, and H : r = ΩK − KΩ (K of a rigidly rotated rest
// shape is Q K Qᵀ; Ω = ω× on every vertex commutes with M), so
//   rᵀ M Φᵢⱼ = (λⱼ − λᵢ) Ψᵢᵀ M Ω Ψⱼ / λᵢ,   tᵀ M Φᵢⱼ = 0 for translations t,
// zero for i = j only. Checked below (measured agreement 1e-9 relative).
TEST_F(FreeDerivatives, MatchDenseBorderedSolveOfEquation2_60) {
  const ModalDerivatives derivatives = compute_modal_derivatives(model, modes);
  const int k = 3;
  ASSERT_EQ(derivatives.pairs.size(), static_cast<std::size_t>(k * k));
  ASSERT_EQ(derivatives.vectors.cols(), k * k);
  EXPECT_GT(derivatives.max_minres_iterations, 0);
  std::set<std::array<int, 2>> seen(derivatives.pairs.begin(), derivatives.pairs.end());
  EXPECT_EQ(seen.size(), derivatives.pairs.size());

  const Eigen::MatrixXd stiffness = dense_stiffness(Eigen::VectorXd::Zero(model.num_dofs()));
  const Eigen::Index n = model.num_dofs();
  for (int i = 0; i < k; ++i) {
    const Eigen::VectorXd m_psi = mass * modes.modes.col(i);
    Eigen::MatrixXd bordered = Eigen::MatrixXd::Zero(n + 1, n + 1);
    bordered.topLeftCorner(n, n) = stiffness - modes.eigenvalues[i] * dense_mass;
    bordered.topRightCorner(n, 1) = m_psi;
    bordered.bottomLeftCorner(1, n) = m_psi.transpose();
    const Eigen::PartialPivLU<Eigen::MatrixXd> lu(bordered);
    for (int j = 0; j < k; ++j) {
      const Eigen::Index c = column_of(derivatives, i, j);
      ASSERT_GE(c, 0) << "pair " << i << "," << j << " missing";
      const Eigen::VectorXd h = hessian_term(model, modes, i, j);
      Eigen::VectorXd rhs = Eigen::VectorXd::Zero(n + 1);
      rhs.head(n) = m_psi * modes.modes.col(i).dot(h) - h;
      const Eigen::VectorXd solution = lu.solve(rhs);
      // μ MΨᵢ is the part of the right-hand side outside the range of K − λᵢM: zero up to the
      // eigenpair's residual (measured ≤ ~1e-10 of ‖b‖).
      EXPECT_LT(std::abs(solution[n]) * m_psi.norm(), 1e-8 * rhs.norm());
      const Eigen::VectorXd phi = derivatives.vectors.col(c);
      EXPECT_LT(relative_error(phi, solution.head(n)), 1e-6) << "Φ" << i << j;
      const double orthogonality = std::abs(m_psi.dot(phi)) / mass_norm(mass, phi);
      EXPECT_LT(orthogonality, 1e-10) << "Φ" << i << j;
    }
  }
  // Rigid content of each Φᵢⱼ, against the identity above.
  const VolumeMesh& mesh = model.mesh();
  const Eigen::Vector3d centre = mesh.vertices.colwise().mean().transpose();
  for (int axis = 0; axis < 6; ++axis) {
    const bool rotation = axis >= 3;
    const Eigen::Vector3d omega = Eigen::Vector3d::Unit(axis % 3);
    Eigen::VectorXd field(n);
    for (Eigen::Index v = 0; v < mesh.num_vertices(); ++v) {
      const Eigen::Vector3d x = mesh.vertices.row(v).transpose() - centre;
      field.segment<3>(3 * v) = rotation ? omega.cross(x) : omega;
    }
    for (const auto& [i, j] : derivatives.pairs) {
      const Eigen::VectorXd phi = derivatives.vectors.col(column_of(derivatives, i, j));
      double expected = 0.0;
      if (rotation) {
        Eigen::VectorXd turned(n);  // Ω Ψⱼ
        for (Eigen::Index v = 0; v < mesh.num_vertices(); ++v) {
          turned.segment<3>(3 * v) =
              omega.cross(Eigen::Vector3d(modes.modes.col(j).segment<3>(3 * v)));
        }
        expected = (modes.eigenvalues[j] - modes.eigenvalues[i]) *
                   modes.modes.col(i).dot(mass * turned) / modes.eigenvalues[i];
      }
      EXPECT_NEAR(field.dot(mass * phi), expected,
                  1e-7 * mass_norm(mass, field) * mass_norm(mass, phi))
          << "Φ" << i << j << ", rigid field " << axis;
    }
  }
  // The inertia terms make the derivatives non-symmetric.
  const double asymmetry = relative_error(derivatives.vectors.col(column_of(derivatives, 0, 1)),
                                          derivatives.vectors.col(column_of(derivatives, 1, 0)));
  EXPECT_GT(asymmetry, 1e-2);
}

/// The eigenvector of K(u) ψ = λ M ψ whose eigenvalue is nearest `shift`, by inverse iteration
/// from `start` (dense LU of K(u) − shift·M), mass-normalized and sign-aligned with `start`.
/// With the shift at the unperturbed eigenvalue λᵢ and u small, the contraction factor per
/// iteration is |λᵢ(u) − λᵢ| / gap ~ 1e-5: four iterations reach round-off.
Eigen::VectorXd tangent_mode(const Eigen::MatrixXd& stiffness, const Eigen::MatrixXd& mass,
                             double shift, const Eigen::VectorXd& start) {
  const Eigen::PartialPivLU<Eigen::MatrixXd> lu(stiffness - shift * mass);
  Eigen::VectorXd psi = start;
  for (int iteration = 0; iteration < 4; ++iteration) {
    psi = lu.solve(mass * psi);
    psi /= std::sqrt(psi.dot(mass * psi));
    if (psi.dot(mass * start) < 0) psi = -psi;
  }
  return psi;
}

// Φᵢⱼ = ∂/∂pⱼ Ψᵢ(Σ Ψₗ pₗ) at p = 0 (eq. 2.45), by central differences of dense tangent
// eigenvectors at u = ±εΨⱼ. Differentiating ΨᵢᵀMΨᵢ = 1 gives Ψᵢᵀ M Φᵢⱼ = 0, the normalization
// eq. 2.60 is solved with, so the difference quotient must match Φᵢⱼ itself. Error O(ε²); ε is
// set so that ε max|Ψⱼ| = 1e-4 of the box length. Measured relative errors over the 9 pairs:
// 1.8e-7 … 9.7e-7 at ε; 4× smaller at ε/2 and 100× larger at 10ε (pure truncation).
TEST_F(FreeDerivatives, AreDerivativesOfTangentModes) {
  ModalDerivativesOptions options;
  options.tolerance = 1e-12;
  const ModalDerivatives derivatives = compute_modal_derivatives(model, modes, options);
  const double epsilon = 1e-4 / modes.modes.cwiseAbs().maxCoeff();
  for (int j = 0; j < 3; ++j) {
    const Eigen::VectorXd direction = modes.modes.col(j);
    const Eigen::MatrixXd plus = dense_stiffness(epsilon * direction);
    const Eigen::MatrixXd minus = dense_stiffness(-epsilon * direction);
    for (int i = 0; i < 3; ++i) {
      const Eigen::VectorXd reference = modes.modes.col(i);
      const double shift = modes.eigenvalues[i];
      const Eigen::VectorXd numeric = (tangent_mode(plus, dense_mass, shift, reference) -
                                       tangent_mode(minus, dense_mass, shift, reference)) /
                                      (2 * epsilon);
      const double error =
          relative_error(derivatives.vectors.col(column_of(derivatives, i, j)), numeric);
      EXPECT_LT(error, 1e-5) << "Φ" << i << j;
    }
  }
}

// Measured: 1.9e-15 (MINRES tolerance 1e-12, 9 iterations either way).
TEST_F(FreeDerivatives, BlockSizeDoesNotChangeTheResult) {
  ModalDerivativesOptions options;
  options.tolerance = 1e-12;
  const ModalDerivatives reference = compute_modal_derivatives(model, modes, options);
  options.block_size = 2;
  const ModalDerivatives blocked = compute_modal_derivatives(model, modes, options);
  ASSERT_EQ(blocked.pairs, reference.pairs);
  EXPECT_LT((blocked.vectors - reference.vectors).norm(), 1e-8 * reference.vectors.norm());
}

// A cube has modes of equal eigenvalue (λ₁ = λ₂, λ₃ = λ₄ = λ₅, λ₆ = λ₇ = λ₈). Along such a
// cluster C of Ψᵢ the derivative is ambiguous, and eq. 2.60 generalizes to
// (K − λᵢM) Φ = (MΨ_CΨ_Cᵀ − I) h with Ψ_Cᵀ M Φ = 0, h = (H : Ψⱼ)Ψᵢ. Checked against the equation
// itself, with K and M assembled apart. Measured: worst residual 4.2e-10 of ‖h‖.
class FreeDerivativesOfACube : public ::testing::Test {
 protected:
  FemModel model{box_hex_mesh({0, 0, 0}, {1, 1, 1}, {3, 3, 3}), {rubber}};
};

TEST_F(FreeDerivativesOfACube, SatisfyEquation2_60AlongClustersOfEqualModes) {
  const LinearModes modes = modes_of(model, {}, 8);
  const Eigen::VectorXd& lambda = modes.eigenvalues;
  ASSERT_NEAR(lambda(7), lambda(5), 1e-6 * lambda(5));  // the test needs whole clusters
  const auto cluster_of = [&](int i) {
    std::vector<int> cluster;
    for (int m = 0; m < lambda.size(); ++m) {
      if (std::abs(lambda(m) - lambda(i)) <= 1e-6 * lambda(i)) cluster.push_back(m);
    }
    return cluster;
  };
  const SparseMatrix mass = model.mass_matrix();
  SparseMatrix stiffness = model.stiffness_pattern();
  model.tangent_stiffness(Eigen::VectorXd::Zero(model.num_dofs()), stiffness);
  const ModalDerivatives derivatives = compute_modal_derivatives(model, modes);
  for (const auto& [i, j] : derivatives.pairs) {
    const Eigen::MatrixXd psi = modes.modes(Eigen::all, cluster_of(i));
    const Eigen::VectorXd h = hessian_term(model, modes, i, j);
    const Eigen::VectorXd phi = derivatives.vectors.col(column_of(derivatives, i, j));
    const Eigen::VectorXd residual =
        stiffness * phi - lambda(i) * (mass * phi) - (mass * (psi * (psi.transpose() * h)) - h);
    EXPECT_LT(residual.norm(), 1e-8 * h.norm()) << "Φ" << i << j;
    EXPECT_LT((psi.transpose() * (mass * phi)).norm(), 1e-10 * mass_norm(mass, phi))
        << "Φ" << i << j;
  }
}

// 7 modes cut the triple λ₆ = λ₇ = λ₈: along Ψ₈ eq. 2.60 has no solution for i = 6, 7. MINRES
// cannot converge, and its error says what to do.
TEST_F(FreeDerivativesOfACube, ModesThatCutAClusterFailWithAReason) {
  const LinearModes modes = modes_of(model, {}, 7);
  try {
    compute_modal_derivatives(model, modes);
    ADD_FAILURE() << "expected a SolverError";
  } catch (const SolverError& error) {
    EXPECT_NE(std::string(error.what()).find("twin of equal eigenvalue past the 7 computed"),
              std::string::npos)
        << error.what();
  }
}

// ---------------------------------------------------------------------------------------------
// Errors, cancellation, progress.

TEST(ModalDerivativesErrors, RejectsModesOfAnotherModelAndBadOptions) {
  const FemModel model(bar(ElementType::hexahedron), {rubber});
  const FemModel other(box_hex_mesh({0, 0, 0}, {1, 0.3, 0.2}, {3, 2, 2}), {rubber});
  const LinearModes modes = modes_of(model, clamped_end(model.mesh()), 2);
  EXPECT_THROW(compute_modal_derivatives(other, modes), Error);
  ModalDerivativesOptions options;
  options.block_size = 0;
  EXPECT_THROW(compute_modal_derivatives(model, modes, options), Error);
  const LinearModes free_modes = modes_of(model, {}, 2);
  options = {};
  options.tolerance = -1.0;
  EXPECT_THROW(compute_modal_derivatives(model, free_modes, options), Error);
  options = {};
  options.max_iterations = 0;
  EXPECT_THROW(compute_modal_derivatives(model, free_modes, options), Error);
}

TEST(ModalDerivativesProgress, CancellationThrows) {
  const FemModel model(bar(ElementType::hexahedron), {rubber});
  const LinearModes anchored = modes_of(model, clamped_end(model.mesh()), 3);
  const LinearModes free = modes_of(model, {}, 3);
  for (const LinearModes* modes : {&anchored, &free}) {
    ModalDerivativesOptions options;
    options.progress = [](const Progress&) { return false; };
    EXPECT_THROW(compute_modal_derivatives(model, *modes, options), Cancelled);
    // Cancelled in the second stage, at its first report.
    options.progress = [](const Progress& p) { return p.stage != "modal derivatives"; };
    EXPECT_THROW(compute_modal_derivatives(model, *modes, options), Cancelled);
  }
}

TEST(ModalDerivativesProgress, ReportsBothStagesInOrder) {
  const FemModel model(bar(ElementType::tetrahedron), {rubber});
  const LinearModes modes = modes_of(model, clamped_end(model.mesh()), 3);
  std::vector<std::string> stages;
  std::vector<Progress> reports;
  ModalDerivativesOptions options;
  options.block_size = 2;
  options.progress = [&](const Progress& p) {
    stages.emplace_back(p.stage);
    reports.push_back(p);
    return true;
  };
  compute_modal_derivatives(model, modes, options);
  ASSERT_FALSE(stages.empty());
  // "Hessian contractions" (one unit per mode) then "modal derivatives" (one per derivative).
  const auto first_derivative = std::find(stages.begin(), stages.end(), "modal derivatives");
  ASSERT_NE(first_derivative, stages.end());
  EXPECT_TRUE(std::all_of(stages.begin(), first_derivative,
                          [](const std::string& s) { return s == "Hessian contractions"; }));
  EXPECT_TRUE(std::all_of(first_derivative, stages.end(),
                          [](const std::string& s) { return s == "modal derivatives"; }));
  const std::size_t split = static_cast<std::size_t>(first_derivative - stages.begin());
  ASSERT_GT(split, 0u);
  EXPECT_EQ(reports[split - 1].done, reports[split - 1].total);
  EXPECT_EQ(reports[split - 1].total, 3);
  EXPECT_EQ(reports.back().done, reports.back().total);
  EXPECT_EQ(reports.back().total, 6);
  for (std::size_t r = 1; r < reports.size(); ++r) {
    EXPECT_LE(reports[r].done, reports[r].total);
    if (stages[r] == stages[r - 1]) {
      EXPECT_GE(reports[r].done, reports[r - 1].done);
    }
  }
}

}  // namespace
}  // namespace khz::reduced
