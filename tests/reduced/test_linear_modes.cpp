// Linear modal analysis K ψ = λ M ψ (thesis eq. 2.43, §2.8.3; free objects §2.8.7), checked
// independently: against Eigen's dense generalized eigensolver on small meshes, against
// Euler–Bernoulli and Saint-Venant beam theory on a clamped beam, and for the rigid modes of
// free-floating objects.
#include <khz/reduced/basis/linear_modes.hpp>
#include <khz/reduced/errors.hpp>
#include <khz/reduced/fem/fem_model.hpp>
#include <khz/reduced/meshing/box_mesh.hpp>
#include <khz/reduced/solvers/fixed_dofs.hpp>

#include <khz/test/cantilever.hpp>
#include <khz/test/element_types.hpp>
#include <khz/test/fixtures.hpp>

#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <numbers>
#include <numeric>
#include <span>
#include <string>
#include <utility>
#include <vector>

namespace khz::reduced {
namespace {

// A generic isotropic material (ν ≠ 0 so every Lamé term matters).
const Material rubber = Material::stvk(1e6, 0.3, 1000.0);
// ν = 0: the 3-D beam then has no Poisson stiffening against the 1-D beam theories.
const Material steel = Material::stvk(200e9, 0.0, 7800.0);

/// A box with three distinct side lengths: its symmetry group (reflections only) has no
/// multi-dimensional representation, so its eigenvalues are simple and the eigenvectors are
/// unique up to sign.
VolumeMesh odd_box(ElementType type) {
  const Eigen::Vector3d min_corner(0, 0, 0), max_corner(1.0, 0.55, 0.3);
  const Eigen::Vector3i cells(4, 3, 2);  // 60 vertices, 180 dofs
  return type == ElementType::tetrahedron ? box_tet_mesh(min_corner, max_corner, cells)
                                          : box_hex_mesh(min_corner, max_corner, cells);
}

/// Vertices on the x = x0 face of a mesh.
std::vector<int> face_x(const VolumeMesh& mesh, double x0) {
  const Eigen::AlignedBox3d box(Eigen::Vector3d(x0 - 1e-9, -1e9, -1e9),
                                Eigen::Vector3d(x0 + 1e-9, 1e9, 1e9));
  return vertices_in_box(mesh.vertices, box);
}

/// Every eigenpair of K(0) ψ = λ M ψ on the free dofs, by Eigen's dense solver (Cholesky of M,
/// then a symmetric QR iteration), with the vectors expanded to the full dofs.
struct DenseModes {
  Eigen::VectorXd values;   ///< Ascending.
  Eigen::MatrixXd vectors;  ///< 3n × free dofs, M-orthonormal.
};

DenseModes dense_modes(const FemModel& model, std::span<const int> fixed, MassLumping lumping) {
  const FixedDofs dofs(model.mesh().num_vertices(), fixed);
  SparseMatrix k = model.stiffness_pattern();
  model.tangent_stiffness(Eigen::VectorXd::Zero(model.num_dofs()), k);
  const Eigen::MatrixXd k_free = Eigen::MatrixXd(dofs.restrict_matrix(k));
  const Eigen::MatrixXd m_free = Eigen::MatrixXd(dofs.restrict_matrix(model.mass_matrix(lumping)));
  const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> solver(k_free, m_free);
  EXPECT_EQ(solver.info(), Eigen::Success);
  DenseModes result;
  result.values = solver.eigenvalues();
  result.vectors.resize(model.num_dofs(), k_free.rows());
  Eigen::VectorXd full;
  for (Eigen::Index c = 0; c < k_free.rows(); ++c) {
    dofs.expand_vector(solver.eigenvectors().col(c), full);
    result.vectors.col(c) = full;
  }
  return result;
}

double mass_norm(const SparseMatrix& mass, const Eigen::VectorXd& v) {
  return std::sqrt(v.dot(mass * v));
}

/// ‖v − P v‖_M / ‖v‖_M with P the M-orthogonal projector onto span(basis), basis M-orthonormal.
double projection_residual(const Eigen::MatrixXd& basis, const SparseMatrix& mass,
                           const Eigen::VectorXd& v) {
  const Eigen::VectorXd rest = v - basis * (basis.transpose() * (mass * v));
  return mass_norm(mass, rest) / mass_norm(mass, v);
}

/// Largest |(ΨᵀMΨ − I)ᵢⱼ|.
double orthonormality_error(const Eigen::MatrixXd& modes, const SparseMatrix& mass) {
  const Eigen::MatrixXd gram = modes.transpose() * (mass * modes);
  return (gram - Eigen::MatrixXd::Identity(gram.rows(), gram.cols())).cwiseAbs().maxCoeff();
}

/// Compares computed modes with the dense reference's eigenpairs first … first + k − 1:
/// eigenvalues relatively, eigenvectors up to sign (both are simple on odd_box, checked here).
/// Returns {max relative eigenvalue error, max ‖ψ ∓ ψ_ref‖_M}.
std::pair<double, double> compare_with_dense(const LinearModes& modes, const DenseModes& dense,
                                             Eigen::Index first, const SparseMatrix& mass) {
  double value_error = 0.0, vector_error = 0.0;
  const Eigen::Index k = modes.eigenvalues.size();
  for (Eigen::Index i = 0; i < k; ++i) {
    const double reference = dense.values[first + i];
    // Up to sign needs simple eigenvalues: check the gaps to both neighbours.
    const Eigen::Index j = first + i;
    double gap = dense.values[j + 1] - reference;
    if (j > 0) gap = std::min(gap, reference - dense.values[j - 1]);
    EXPECT_GT(gap, 1e-3 * reference) << "mode " << i << " is not simple";
    value_error = std::max(value_error, std::abs(modes.eigenvalues[i] - reference) / reference);
    const Eigen::VectorXd psi = modes.modes.col(i);
    const Eigen::VectorXd ref = dense.vectors.col(first + i);
    const double sign = psi.dot(mass * ref) >= 0 ? 1.0 : -1.0;
    vector_error = std::max(vector_error, mass_norm(mass, psi - sign * ref));
  }
  return {value_error, vector_error};
}

class LinearModesDense : public ::testing::TestWithParam<ElementType> {};

// Constrained: the eigenproblem on the free dofs (x = 0 face clamped), k = 8 of 165.
// Measured (tetrahedra / hexahedra): eigenvalue errors 1.1e-12 / 2.6e-13, eigenvector errors
// (M-norm) 1.4e-12 / 4.9e-13, |ΨᵀMΨ − I| 1.9e-15, relative eigen-residuals ≤ 2.9e-13.
TEST_P(LinearModesDense, ConstrainedMatchesDenseSolver) {
  const FemModel model(odd_box(GetParam()), {rubber});
  const std::vector<int> clamped = face_x(model.mesh(), 0.0);
  LinearModesOptions options;
  options.num_modes = 8;
  const LinearModes modes = compute_linear_modes(model, clamped, options);
  const DenseModes dense = dense_modes(model, clamped, MassLumping::consistent);
  const SparseMatrix mass = model.mass_matrix();

  ASSERT_EQ(modes.eigenvalues.size(), 8);
  ASSERT_EQ(modes.modes.rows(), model.num_dofs());
  ASSERT_EQ(modes.modes.cols(), 8);
  EXPECT_EQ(modes.rigid_eigenvalues.size(), 0);
  EXPECT_EQ(modes.rigid_modes.cols(), 0);
  EXPECT_FALSE(modes.unconstrained());
  EXPECT_EQ(modes.fixed_vertices, clamped);
  for (Eigen::Index i = 1; i < 8; ++i) EXPECT_LE(modes.eigenvalues[i - 1], modes.eigenvalues[i]);

  const auto [value_error, vector_error] = compare_with_dense(modes, dense, 0, mass);
  EXPECT_LT(value_error, 1e-8);
  EXPECT_LT(vector_error, 1e-8);
  EXPECT_LT(orthonormality_error(modes.modes, mass), 1e-10);
  for (int v : clamped) EXPECT_EQ(modes.modes.middleRows(3 * v, 3).cwiseAbs().maxCoeff(), 0.0);

  // K Ψ = M Ψ Λ on the free dofs (residual relative to ‖K ψ‖).
  const FixedDofs dofs(model.mesh().num_vertices(), clamped);
  SparseMatrix k = model.stiffness_pattern();
  model.tangent_stiffness(Eigen::VectorXd::Zero(model.num_dofs()), k);
  for (Eigen::Index i = 0; i < 8; ++i) {
    const Eigen::VectorXd kpsi = k * modes.modes.col(i);
    const Eigen::VectorXd residual =
        dofs.restrict_vector(kpsi - modes.eigenvalues[i] * (mass * modes.modes.col(i)));
    EXPECT_LT(residual.norm(), 1e-9 * dofs.restrict_vector(kpsi).norm()) << "mode " << i;
  }

  const Eigen::VectorXd hz = modes.frequencies_hz();
  ASSERT_EQ(hz.size(), 8);
  for (Eigen::Index i = 0; i < 8; ++i) {
    EXPECT_NEAR(hz[i], std::sqrt(modes.eigenvalues[i]) / (2 * std::numbers::pi), 1e-12 * hz[i]);
  }
}

// Unconstrained: the dense solver's first six eigenvalues are the rigid ones (round-off), the
// deformation modes follow. Measured (tetrahedra / hexahedra): eigenvalue errors 1.4e-11 /
// 1.8e-11, eigenvector errors 7.7e-11 / 3.1e-11.
TEST_P(LinearModesDense, UnconstrainedMatchesDenseSolver) {
  const FemModel model(odd_box(GetParam()), {rubber});
  LinearModesOptions options;
  options.num_modes = 6;
  const LinearModes modes = compute_linear_modes(model, {}, options);
  const DenseModes dense = dense_modes(model, {}, MassLumping::consistent);
  const SparseMatrix mass = model.mass_matrix();

  EXPECT_TRUE(modes.unconstrained());
  ASSERT_EQ(modes.eigenvalues.size(), 6);
  ASSERT_EQ(modes.rigid_eigenvalues.size(), 6);
  ASSERT_EQ(modes.rigid_modes.cols(), 6);
  ASSERT_EQ(modes.rigid_modes.rows(), model.num_dofs());
  EXPECT_LT(dense.values.head(6).cwiseAbs().maxCoeff(), 1e-8 * dense.values[6]);  // sanity
  const auto [value_error, vector_error] = compare_with_dense(modes, dense, 6, mass);
  EXPECT_LT(value_error, 1e-8);
  EXPECT_LT(vector_error, 1e-8);
  EXPECT_LT(orthonormality_error(modes.modes, mass), 1e-10);
  EXPECT_LT(modes.rigid_eigenvalues.cwiseAbs().maxCoeff(), 1e-6 * modes.eigenvalues[0]);
}

// Row-sum lumped mass: the same comparison with the diagonal mass matrix, and Ψᵀ M_lumped Ψ = I.
// Measured (tetrahedra / hexahedra): eigenvalues 1.5e-13 / 8.2e-13, eigenvectors 1.8e-13 /
// 8.4e-14.
TEST_P(LinearModesDense, LumpedMassMatchesDenseSolver) {
  const FemModel model(odd_box(GetParam()), {rubber});
  const std::vector<int> clamped = face_x(model.mesh(), 0.0);
  LinearModesOptions options;
  options.num_modes = 5;
  options.mass = MassLumping::lumped;
  const LinearModes modes = compute_linear_modes(model, clamped, options);
  const DenseModes dense = dense_modes(model, clamped, MassLumping::lumped);
  const SparseMatrix lumped = model.mass_matrix(MassLumping::lumped);
  const auto [value_error, vector_error] = compare_with_dense(modes, dense, 0, lumped);
  EXPECT_LT(value_error, 1e-8);
  EXPECT_LT(vector_error, 1e-8);
  EXPECT_LT(orthonormality_error(modes.modes, lumped), 1e-10);
}

INSTANTIATE_TEST_SUITE_P(ElementTypes, LinearModesDense,
                         ::testing::ValuesIn(test::all_element_types), test::element_type_name);

// ---------------------------------------------------------------------------------------------
// Beam theory. The mode shapes are told apart by their displacement fields, not their indices:
// per cross-section (vertices with equal x) the mass-weighted mean transverse displacement is
// the beam deflection, the mass-weighted best-fit rotation about the beam axis is the twist.

/// Vertex masses (row sums of M), length n.
Eigen::VectorXd vertex_masses(const FemModel& model) {
  const SparseMatrix mass = model.mass_matrix(MassLumping::lumped);
  Eigen::VectorXd masses(model.mesh().num_vertices());
  for (Eigen::Index v = 0; v < masses.size(); ++v) masses[v] = mass.coeff(3 * v, 3 * v);
  return masses;
}

struct ModeShapeShares {
  double bending = 0;  ///< Share of ‖ψ‖²_M in the section-mean transverse displacements.
  double torsion = 0;  ///< Share of ‖ψ‖²_M in the section-wise rigid rotations about the axis.
};

/// Shares of a mode's (lumped) kinetic energy carried by bending and by twisting of the cross
/// sections of a beam along x whose axis passes through `centre` (y, z).
ModeShapeShares mode_shape_shares(const VolumeMesh& mesh, const Eigen::VectorXd& masses,
                                  const Eigen::Vector2d& centre, const Eigen::VectorXd& psi,
                                  double section_spacing) {
  const Eigen::Index n = mesh.num_vertices();
  int sections = 0;
  for (Eigen::Index v = 0; v < n; ++v) {
    sections =
        std::max(sections, static_cast<int>(std::lround(mesh.vertices(v, 0) / section_spacing)));
  }
  ++sections;
  std::vector<double> mass(sections, 0.0), inertia(sections, 0.0), moment(sections, 0.0);
  std::vector<Eigen::Vector2d> transverse(sections, Eigen::Vector2d::Zero());
  double total = 0.0;
  for (Eigen::Index v = 0; v < n; ++v) {
    const int s = static_cast<int>(std::lround(mesh.vertices(v, 0) / section_spacing));
    const Eigen::Vector2d r(mesh.vertices(v, 1) - centre.x(), mesh.vertices(v, 2) - centre.y());
    const Eigen::Vector2d tangent(-r.y(), r.x());  // e_x × r
    const Eigen::Vector2d u_t(psi[3 * v + 1], psi[3 * v + 2]);
    mass[s] += masses[v];
    transverse[s] += masses[v] * u_t;
    moment[s] += masses[v] * u_t.dot(tangent);
    inertia[s] += masses[v] * r.squaredNorm();
    total += masses[v] * psi.segment<3>(3 * v).squaredNorm();
  }
  ModeShapeShares shares;
  for (int s = 0; s < sections; ++s) {
    // Mean deflection ū = Σmu/Σm carries Σm |ū|²; best-fit angle θ = Σ m u·t / Σ m|r|² carries
    // θ² Σ m|r|².
    shares.bending += transverse[s].squaredNorm() / mass[s];
    if (inertia[s] > 0) shares.torsion += moment[s] * moment[s] / inertia[s];
  }
  shares.bending /= total;
  shares.torsion /= total;
  return shares;
}

struct BeamFrequencyErrors {
  double first_bending = 0;   ///< Worst relative error of the two first bending modes.
  double second_bending = 0;  ///< Worst relative error of the two second bending modes.
  double torsion = 0;         ///< Relative error of the first torsion mode.
};

/// A 1 m × 0.1 m × 0.1 m steel cantilever with `across` hexahedra through the side, against
/// Euler–Bernoulli bending, f = (βL)²/(2π) √(EI/(ρAL⁴)) with βL = 1.8751, 4.6941 (each a
/// degenerate pair for the square section), and Saint-Venant torsion of a clamped-free shaft,
/// f = (1/4L) √(GJ/(ρI_p)) with J = 0.1406 a⁴ and I_p = a⁴/6 for the square of side a.
BeamFrequencyErrors beam_frequency_errors(int across) {
  const test::Cantilever beam(1.0, 0.1, across, steel);
  LinearModesOptions options;
  options.num_modes = 8;  // bending pairs 1 and 2, torsion 1, axial 1 (and bending pair 3)
  const LinearModes modes = compute_linear_modes(beam.model, beam.clamped, options);
  const Eigen::VectorXd hz = modes.frequencies_hz();

  const double young = 200e9, shear = young / 2.0, density = 7800.0;
  const double a = beam.side, length = beam.length;
  const double area = a * a, inertia = std::pow(a, 4) / 12.0;
  const double bending_scale =
      std::sqrt(young * inertia / (density * area * std::pow(length, 4))) / (2 * std::numbers::pi);
  const double first = 1.8751 * 1.8751 * bending_scale;
  // The second mode's half-wavelength is only ~7 beam depths: shear deformation and rotary
  // inertia lower its frequency by ½(βr)²(1 + E/κG) to first order in (βr)² (Timoshenko; r the
  // radius of gyration a/√12, κ = 10(1+ν)/(12+11ν) = 5/6): 3.1 % here, 0.5 % for the first
  // mode, which is compared uncorrected.
  const double beta_r = 4.6941 / length * a / std::sqrt(12.0);
  const double timoshenko = 1.0 - 0.5 * beta_r * beta_r * (1.0 + young / (5.0 / 6.0 * shear));
  const double second = 4.6941 * 4.6941 * bending_scale * timoshenko;
  const double torsion_constant = 0.1406 * std::pow(a, 4), polar = std::pow(a, 4) / 6.0;
  const double torsion = std::sqrt(shear * torsion_constant / (density * polar)) / (4 * length);

  const Eigen::VectorXd masses = vertex_masses(beam.model);
  std::vector<Eigen::Index> bending;
  Eigen::Index twist = -1;
  double best_torsion = 0.0;
  for (Eigen::Index i = 0; i < hz.size(); ++i) {
    const ModeShapeShares shares = mode_shape_shares(
        beam.model.mesh(), masses, Eigen::Vector2d(a / 2, a / 2), modes.modes.col(i), a / across);
    if (shares.bending > 0.5) bending.push_back(i);
    if (shares.torsion > best_torsion) {
      best_torsion = shares.torsion;
      twist = i;
    }
  }
  EXPECT_GE(bending.size(), 4u);
  EXPECT_GT(best_torsion, 0.8);
  BeamFrequencyErrors errors;
  if (bending.size() < 4 || twist < 0) return errors;
  for (int pair = 0; pair < 2; ++pair) {
    const double expected = pair == 0 ? first : second;
    double& error = pair == 0 ? errors.first_bending : errors.second_bending;
    for (int member = 0; member < 2; ++member) {
      error = std::max(error, std::abs(hz[bending[2 * pair + member]] - expected) / expected);
    }
  }
  errors.torsion = std::abs(hz[twist] - torsion) / torsion;
  return errors;
}

// Trilinear hexahedra are too stiff in bending (parasitic shear), so the frequencies come out
// high and converge from above as the section is refined. Measured (Hz; reference in brackets):
//   2 cells across (80 hexahedra):  bending 86.25 ×2 [81.80] +5.4 %, 524.45 ×2 [496.63] +5.6 %,
//                                   torsion 895.37 [822.17] +8.9 %
//   4 cells across (640 hexahedra): bending 82.54 ×2 +0.91 %, 499.50 ×2 +0.58 %,
//                                   torsion 844.71 +2.7 %
// Against plain Euler–Bernoulli (512.6 Hz) the fine second bending pair is −2.6 %: the
// Timoshenko effect, which the coarse mesh's stiffening (+2.3 %) happens to mask. The torsion
// mode carries 0.9+ of its kinetic energy in section rotations, the bending modes 0. 6 cells
// across (2160 hexahedra) would take several seconds in a Debug build.
TEST(LinearModesBeam, CantileverMatchesBeamTheory) {
  const BeamFrequencyErrors coarse = beam_frequency_errors(2);
  const BeamFrequencyErrors fine = beam_frequency_errors(4);
  EXPECT_LT(fine.first_bending, coarse.first_bending);
  EXPECT_LT(fine.second_bending, coarse.second_bending);
  EXPECT_LT(fine.torsion, coarse.torsion);
  EXPECT_LT(fine.first_bending, 0.02);
  EXPECT_LT(fine.second_bending, 0.02);
  EXPECT_LT(fine.torsion, 0.05);
}

// ---------------------------------------------------------------------------------------------
// Free-floating objects (§2.8.7).

/// The 6 rigid velocity fields of the vertices in [first, last): translations along x, y, z and
/// rotations about axes through `centre`, zero elsewhere.
Eigen::MatrixXd rigid_fields(const VolumeMesh& mesh, Eigen::Index first, Eigen::Index last,
                             const Eigen::Vector3d& centre) {
  Eigen::MatrixXd fields = Eigen::MatrixXd::Zero(3 * mesh.num_vertices(), 6);
  for (Eigen::Index v = first; v < last; ++v) {
    const Eigen::Vector3d r = mesh.vertices.row(v).transpose() - centre;
    for (int axis = 0; axis < 3; ++axis) {
      fields(3 * v + axis, axis) = 1.0;
      fields.block<3, 1>(3 * v, 3 + axis) = Eigen::Vector3d::Unit(axis).cross(r);
    }
  }
  return fields;
}

// Measured: rigid eigenvalues ≤ 5.4e-15 λ₁; projection residuals of the analytic rigid fields
// ≤ 2.3e-15; |RᵀMΨ| 1.6e-16.
TEST(LinearModesFree, RigidModesSpanTranslationsAndRotations) {
  const FemModel model(odd_box(ElementType::hexahedron), {rubber});
  LinearModesOptions options;
  options.num_modes = 4;
  const LinearModes modes = compute_linear_modes(model, {}, options);
  const SparseMatrix mass = model.mass_matrix();
  ASSERT_EQ(modes.rigid_eigenvalues.size(), 6);
  ASSERT_EQ(modes.rigid_modes.cols(), 6);
  EXPECT_LT(modes.rigid_eigenvalues.cwiseAbs().maxCoeff(), 1e-6 * modes.eigenvalues[0]);
  EXPECT_LT(orthonormality_error(modes.rigid_modes, mass), 1e-10);
  const Eigen::MatrixXd fields =
      rigid_fields(model.mesh(), 0, model.mesh().num_vertices(), Eigen::Vector3d(0.5, 0.2, 0.1));
  for (int c = 0; c < 6; ++c) {
    EXPECT_LT(projection_residual(modes.rigid_modes, mass, fields.col(c)), 1e-8) << "field " << c;
  }
  // Deformation modes are M-orthogonal to the rigid ones (which are normalized, as is Ψ).
  EXPECT_LT((modes.rigid_modes.transpose() * (mass * modes.modes)).cwiseAbs().maxCoeff(), 1e-8);
  // The deformation modes store no rigid motion: each analytic field is M-orthogonal to Ψ.
  for (int c = 0; c < 6; ++c) {
    const double norm = mass_norm(mass, fields.col(c));
    EXPECT_LT((modes.modes.transpose() * (mass * fields.col(c))).cwiseAbs().maxCoeff(),
              1e-8 * norm);
  }
}

/// Two disjoint boxes in one mesh: a 2-component object.
VolumeMesh two_boxes() {
  const VolumeMesh a = box_hex_mesh({0, 0, 0}, {1.0, 0.4, 0.3}, {4, 2, 2});
  const VolumeMesh b = box_hex_mesh({2, 0, 0}, {2.5, 0.6, 0.35}, {3, 3, 2});
  VolumeMesh mesh;
  mesh.element_type = ElementType::hexahedron;
  mesh.vertices.resize(a.num_vertices() + b.num_vertices(), 3);
  mesh.vertices << a.vertices, b.vertices;
  mesh.elements.resize(a.num_elements() + b.num_elements(), 8);
  mesh.elements << a.elements, (b.elements.array() + static_cast<int>(a.num_vertices())).matrix();
  return mesh;
}

TEST(LinearModesFree, TwoComponentsHaveTwelveRigidModes) {
  const VolumeMesh mesh = two_boxes();
  const Eigen::Index split = box_hex_mesh({0, 0, 0}, {1.0, 0.4, 0.3}, {4, 2, 2}).num_vertices();
  const FemModel model(mesh, {rubber});
  LinearModesOptions options;
  options.num_modes = 4;
  const LinearModes modes = compute_linear_modes(model, {}, options);
  const SparseMatrix mass = model.mass_matrix();
  ASSERT_EQ(modes.rigid_eigenvalues.size(), 12);
  ASSERT_EQ(modes.rigid_modes.cols(), 12);
  EXPECT_LT(modes.rigid_eigenvalues.cwiseAbs().maxCoeff(), 1e-6 * modes.eigenvalues[0]);
  EXPECT_LT(orthonormality_error(modes.rigid_modes, mass), 1e-10);
  Eigen::MatrixXd fields(model.num_dofs(), 12);
  fields << rigid_fields(mesh, 0, split, Eigen::Vector3d(0.5, 0.2, 0.15)),
      rigid_fields(mesh, split, mesh.num_vertices(), Eigen::Vector3d(2.25, 0.3, 0.2));
  for (int c = 0; c < 12; ++c) {
    EXPECT_LT(projection_residual(modes.rigid_modes, mass, fields.col(c)), 1e-8) << "field " << c;
  }
  EXPECT_LT((modes.rigid_modes.transpose() * (mass * modes.modes)).cwiseAbs().maxCoeff(), 1e-8);
  // The deformation modes are the union of the two boxes' own, each computed alone.
  std::vector<double> separate;
  for (const VolumeMesh& box : {box_hex_mesh({0, 0, 0}, {1.0, 0.4, 0.3}, {4, 2, 2}),
                                box_hex_mesh({2, 0, 0}, {2.5, 0.6, 0.35}, {3, 3, 2})}) {
    const LinearModes alone = compute_linear_modes(FemModel(box, {rubber}), {}, options);
    separate.insert(separate.end(), alone.eigenvalues.begin(), alone.eigenvalues.end());
  }
  std::sort(separate.begin(), separate.end());
  for (Eigen::Index i = 0; i < 4; ++i) {
    EXPECT_NEAR(modes.eigenvalues[i], separate[i], 1e-8 * separate[i]) << "mode " << i;
  }
}

// ---------------------------------------------------------------------------------------------
// Errors, cancellation, progress.

bool mentions_rigid_or_singular(std::string message) {
  std::transform(message.begin(), message.end(), message.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return message.find("rigid") != std::string::npos ||
         message.find("singular") != std::string::npos;
}

/// Succeeds if compute_linear_modes throws a SolverError that says why (rigid motion / singular).
::testing::AssertionResult throws_singular(const FemModel& model, const std::vector<int>& fixed) {
  LinearModesOptions options;
  options.num_modes = 3;
  try {
    compute_linear_modes(model, fixed, options);
  } catch (const SolverError& error) {
    if (mentions_rigid_or_singular(error.what())) return ::testing::AssertionSuccess();
    return ::testing::AssertionFailure() << "message lacks rigid/singular: " << error.what();
  } catch (const std::exception& error) {
    return ::testing::AssertionFailure() << "wrong exception type: " << error.what();
  }
  return ::testing::AssertionFailure() << "did not throw";
}

TEST(LinearModesErrors, RejectsInvalidOptionsAndVertices) {
  const FemModel model(box_hex_mesh({0, 0, 0}, {1, 0.5, 0.4}, {2, 1, 1}), {rubber});  // 36 dofs
  const std::vector<int> clamped = face_x(model.mesh(), 0.0);                         // 4 vertices
  LinearModesOptions options;
  for (int k : {0, -1}) {
    options.num_modes = k;
    EXPECT_THROW(compute_linear_modes(model, clamped, options), Error) << "k = " << k;
  }
  // 24 free dofs when clamped, 36 − 6 rigid when free: k reaching them is too many.
  options.num_modes = 24;
  EXPECT_THROW(compute_linear_modes(model, clamped, options), Error);
  options.num_modes = 30;
  EXPECT_THROW(compute_linear_modes(model, {}, options), Error);
  options.num_modes = 1000;
  EXPECT_THROW(compute_linear_modes(model, {}, options), Error);
  std::vector<int> every_vertex(static_cast<std::size_t>(model.mesh().num_vertices()));
  std::iota(every_vertex.begin(), every_vertex.end(), 0);
  options.num_modes = 6;
  EXPECT_TRUE(test::throws_with_message<Error>(
      [&] { compute_linear_modes(model, every_vertex, options); },
      "6 modes need more than the 0 free dofs of the mesh (every vertex is fixed)"));
  options.num_modes = 2;
  options.tolerance = -1.0;
  EXPECT_THROW(compute_linear_modes(model, clamped, options), Error);
  options.tolerance = 0.0;
  const int n = static_cast<int>(model.mesh().num_vertices());
  for (int bad : {-1, n}) {
    std::vector<int> fixed = clamped;
    fixed.push_back(bad);
    EXPECT_THROW(compute_linear_modes(model, fixed, options), Error) << "vertex " << bad;
  }
}

TEST(LinearModesErrors, FixedVerticesAreSortedAndDeduplicated) {
  const FemModel model(box_hex_mesh({0, 0, 0}, {1, 0.5, 0.4}, {2, 1, 1}), {rubber});
  std::vector<int> clamped = face_x(model.mesh(), 0.0);
  std::vector<int> shuffled(clamped.rbegin(), clamped.rend());
  shuffled.push_back(clamped.front());
  LinearModesOptions options;
  options.num_modes = 2;
  const LinearModes modes = compute_linear_modes(model, shuffled, options);
  EXPECT_EQ(modes.fixed_vertices, clamped);
}

TEST(LinearModesErrors, AnchorsLeavingRigidMotionAreReported) {
  const FemModel model(box_hex_mesh({0, 0, 0}, {1, 0.5, 0.4}, {4, 2, 2}), {rubber});
  // Lattice (i, j, k) is vertex i + 5 (j + 3 k). Two corners: the rotation about the line
  // through them is left. One vertex: all three rotations. A whole edge of collinear vertices
  // (x axis, j = k = 0): the rotation about that edge.
  EXPECT_TRUE(throws_singular(model, {0, 4}));
  EXPECT_TRUE(throws_singular(model, {7}));
  EXPECT_TRUE(throws_singular(model, {0, 1, 2, 3, 4}));
  // Two components, only one anchored.
  const FemModel pair(two_boxes(), {rubber});
  EXPECT_TRUE(throws_singular(pair, face_x(pair.mesh(), 0.0)));
}

TEST(LinearModesProgress, CancellationThrows) {
  const FemModel model(odd_box(ElementType::hexahedron), {rubber});
  const std::vector<int> clamped = face_x(model.mesh(), 0.0);
  LinearModesOptions options;
  options.num_modes = 4;
  options.progress = [](const Progress&) { return false; };
  EXPECT_THROW(compute_linear_modes(model, clamped, options), Cancelled);
  EXPECT_THROW(compute_linear_modes(model, {}, options), Cancelled);
  // Cancelling later, within the Lanczos iteration.
  int calls = 0;
  options.progress = [&calls](const Progress&) { return ++calls < 3; };
  EXPECT_THROW(compute_linear_modes(model, clamped, options), Cancelled);
  EXPECT_EQ(calls, 3);  // stopped at the next check: no further reports
}

TEST(LinearModesProgress, ReportsGoForwardAndFinish) {
  const FemModel model(odd_box(ElementType::tetrahedron), {rubber});
  for (bool anchored : {true, false}) {
    const std::vector<int> fixed = anchored ? face_x(model.mesh(), 0.0) : std::vector<int>{};
    std::vector<Progress> reports;
    std::vector<std::string> stages;
    LinearModesOptions options;
    options.num_modes = 4;
    options.progress = [&](const Progress& p) {
      reports.push_back(p);
      stages.emplace_back(p.stage);
      return true;
    };
    compute_linear_modes(model, fixed, options);
    ASSERT_GE(reports.size(), 2u);
    EXPECT_EQ(reports.front().done, 0);
    EXPECT_EQ(reports.back().done, reports.back().total);
    for (std::size_t i = 0; i < reports.size(); ++i) {
      EXPECT_EQ(stages[i], "linear modes");
      EXPECT_GE(reports[i].total, 1);
      EXPECT_GE(reports[i].done, 0);
      EXPECT_LE(reports[i].done, reports[i].total);
      if (i > 0) {
        EXPECT_GE(reports[i].done, reports[i - 1].done) << "report " << i;
        EXPECT_GE(reports[i].fraction(), reports[i - 1].fraction()) << "report " << i;
      }
    }
  }
}

}  // namespace
}  // namespace khz::reduced
