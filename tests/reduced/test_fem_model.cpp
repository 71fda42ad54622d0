// FemModel construction, quadrature data, the stiffness pattern, parallel assembly and the
// free-body (unconstrained) stiffness.
#include <khz/reduced/errors.hpp>
#include <khz/reduced/fem/element_shape.hpp>
#include <khz/reduced/fem/fem_model.hpp>
#include <khz/reduced/meshing/box_mesh.hpp>
#include <khz/test/fixtures.hpp>

#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <random>
#include <vector>

namespace khz::reduced {
namespace {

using test::throws_with_message;

const Material rubber = Material::stvk(1e6, 0.45, 1100.0);

VolumeMesh unit_box(ElementType type, const Eigen::Vector3i& cells) {
  const Eigen::Vector3d min_corner(0, 0, 0), max_corner(1, 1, 1);
  return type == ElementType::tetrahedron ? box_tet_mesh(min_corner, max_corner, cells)
                                          : box_hex_mesh(min_corner, max_corner, cells);
}

Eigen::VectorXd random_displacement(Eigen::Index dofs, double size, unsigned seed) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> entry(-size, size);
  Eigen::VectorXd u(dofs);
  for (Eigen::Index i = 0; i < dofs; ++i) u[i] = entry(random);
  return u;
}

TEST(FemModel, RejectsInvertedTetrahedronByIndex) {
  VolumeMesh mesh = unit_box(ElementType::tetrahedron, {2, 2, 2});
  std::swap(mesh.elements(17, 0), mesh.elements(17, 1));
  try {
    FemModel model(mesh, {rubber});
    FAIL() << "an inverted element was accepted";
  } catch (const MeshError& error) {
    EXPECT_EQ(error.element(), 17);
    EXPECT_NE(std::string(error.what()).find("element 17"), std::string::npos) << error.what();
  }
}

TEST(FemModel, RejectsInvertedHexahedronByIndex) {
  VolumeMesh mesh = unit_box(ElementType::hexahedron, {2, 2, 2});
  // Mirror element 5 by swapping its bottom and top faces.
  for (int a = 0; a < 4; ++a) std::swap(mesh.elements(5, a), mesh.elements(5, a + 4));
  try {
    FemModel model(mesh, {rubber});
    FAIL() << "an inverted element was accepted";
  } catch (const MeshError& error) {
    EXPECT_EQ(error.element(), 5);
  }
}

TEST(FemModel, RejectsMeshFailingValidation) {
  VolumeMesh mesh = unit_box(ElementType::tetrahedron, {1, 1, 1});
  mesh.elements(2, 3) = 99;
  EXPECT_THROW(FemModel(mesh, {rubber}), MeshError);
}

TEST(FemModel, RejectsGroupWithoutMaterial) {
  VolumeMesh mesh = unit_box(ElementType::tetrahedron, {1, 1, 1});
  mesh.element_groups = Eigen::VectorXi::Zero(mesh.num_elements());
  mesh.element_groups[4] = 2;
  EXPECT_TRUE(throws_with_message<Error>(
      [&] {
        FemModel(mesh, {rubber, rubber});
      },
      "element 4 is in material group 2 but only 2 materials"));
  EXPECT_TRUE(
      throws_with_message<Error>([&] { FemModel(mesh, {}); }, "needs at least one material"));
}

TEST(FemModel, AssignsMaterialsByGroup) {
  VolumeMesh mesh = unit_box(ElementType::hexahedron, {2, 1, 1});
  mesh.element_groups.resize(2);
  mesh.element_groups << 1, 0;
  const Material steel = Material::stvk(2e11, 0.3, 7800.0);
  const FemModel model(mesh, {rubber, steel});
  EXPECT_EQ(model.element_material(0).density(), steel.density());
  EXPECT_EQ(model.element_material(1).density(), rubber.density());
  EXPECT_EQ(model.materials().size(), 2u);
}

TEST(FemModel, MeshWithoutElementsHasNoStiffness) {
  VolumeMesh mesh;
  mesh.vertices = Eigen::MatrixXd::Random(3, 3);
  mesh.elements.resize(0, 4);
  const FemModel model(mesh, {rubber});
  const Eigen::VectorXd u = Eigen::VectorXd::Ones(9);
  Eigen::VectorXd forces;
  model.internal_forces(u, forces);
  EXPECT_EQ(forces, Eigen::VectorXd::Zero(9));
  EXPECT_EQ(model.strain_energy(u), 0.0);
  EXPECT_EQ(model.stiffness_pattern().nonZeros(), 0);
  EXPECT_EQ(model.mass_matrix().nonZeros(), 0);
}

TEST(FemModel, QuadratureWeightsSumToElementVolumes) {
  // A sheared, stretched parallelepiped box, so weights are not all equal to a cube's.
  VolumeMesh tets = unit_box(ElementType::tetrahedron, {2, 3, 1});
  VolumeMesh hexes = unit_box(ElementType::hexahedron, {2, 3, 1});
  Eigen::Matrix3d map;
  map << 2.0, 0.3, 0.0, 0.0, 1.5, 0.2, 0.1, 0.0, 0.7;
  tets.vertices = tets.vertices * map.transpose();
  hexes.vertices = hexes.vertices * map.transpose();
  for (const VolumeMesh& mesh : {tets, hexes}) {
    const FemModel model(mesh, {rubber});
    double total = 0.0;
    for (Eigen::Index e = 0; e < mesh.num_elements(); ++e) {
      for (int q = 0; q < model.quadrature_points_per_element(); ++q) {
        EXPECT_GT(model.quadrature_weight(e, q), 0.0);
        total += model.quadrature_weight(e, q);
      }
    }
    EXPECT_NEAR(total, map.determinant(), 1e-14);  // measured 1.8e-15
  }
  EXPECT_EQ(FemModel(tets, {rubber}).quadrature_points_per_element(), 1);
  EXPECT_EQ(FemModel(hexes, {rubber}).quadrature_points_per_element(), 8);
}

TEST(FemModel, ShapeGradientsMatchElementShapeFunctions) {
  const VolumeMesh mesh = unit_box(ElementType::tetrahedron, {1, 2, 1});
  const FemModel model(mesh, {rubber});
  TetCorners corners;
  for (int a = 0; a < 4; ++a) corners.row(a) = mesh.vertices.row(mesh.elements(7, a));
  const auto gradients = model.shape_gradients(7, 0);
  ASSERT_EQ(gradients.rows(), 4);
  EXPECT_EQ(Eigen::MatrixXd(gradients), Eigen::MatrixXd(tet_shape_gradients(corners)));
  EXPECT_EQ(model.num_dofs(), 3 * mesh.num_vertices());
}

TEST(FemModel, StiffnessPatternHasFullBlocksForVerticesSharingAnElement) {
  // Two hexahedra side by side: 12 vertices; the 4 shared ones see all 12, the others 8.
  const FemModel model(unit_box(ElementType::hexahedron, {2, 1, 1}), {rubber});
  const SparseMatrix pattern = model.stiffness_pattern();
  EXPECT_EQ(pattern.nonZeros(), 9 * (4 * 12 + 8 * 8));
  EXPECT_EQ(pattern.coeffs().cwiseAbs().maxCoeff(), 0.0);
  EXPECT_TRUE(pattern.isCompressed());
  // Vertices 0 (x = 0) and 2 (x = 1) share no element: no block.
  SparseMatrix ones = pattern;
  ones.coeffs().setOnes();
  const Eigen::MatrixXd structure(ones);
  EXPECT_EQ((structure.block<3, 3>(0, 6).sum()), 0.0);
  EXPECT_EQ((structure.block<3, 3>(0, 3).sum()), 9.0);
  EXPECT_EQ((structure.block<3, 3>(3, 0).sum()), 9.0);
}

TEST(FemModel, AssemblesRepeatedlyIntoTheSamePattern) {
  const FemModel model(unit_box(ElementType::tetrahedron, {2, 2, 2}), {rubber});
  SparseMatrix k = model.stiffness_pattern();
  const Eigen::Index nonzeros = k.nonZeros();
  const std::vector<int> inner(k.innerIndexPtr(), k.innerIndexPtr() + nonzeros);
  for (unsigned seed = 1; seed <= 3; ++seed) {
    const Eigen::VectorXd u = random_displacement(model.num_dofs(), 0.1, seed);
    model.tangent_stiffness(u, k);
    EXPECT_EQ(k.nonZeros(), nonzeros);
    EXPECT_EQ(std::vector<int>(k.innerIndexPtr(), k.innerIndexPtr() + nonzeros), inner);
    // Assembly overwrites: the result matches the same call into a fresh pattern exactly.
    SparseMatrix fresh = model.stiffness_pattern();
    model.tangent_stiffness(u, fresh);
    EXPECT_EQ(Eigen::MatrixXd(k), Eigen::MatrixXd(fresh));
  }
}

// One pass and two passes are separately compiled copies of the element loop, which may fuse
// multiply-adds differently on another CPU: equal to round-off of the largest entry (measured
// here: bit for bit).
TEST(FemModel, ForcesAndStiffnessTogetherMatchSeparateCalls) {
  const FemModel model(unit_box(ElementType::hexahedron, {2, 2, 1}), {rubber});
  const Eigen::VectorXd u = random_displacement(model.num_dofs(), 0.2, 4);
  Eigen::VectorXd forces, together;
  model.internal_forces(u, forces);
  SparseMatrix k = model.stiffness_pattern(), k_together = model.stiffness_pattern();
  model.tangent_stiffness(u, k);
  model.forces_and_stiffness(u, together, k_together);
  EXPECT_LE((forces - together).cwiseAbs().maxCoeff(), 1e-14 * forces.cwiseAbs().maxCoeff());
  const Eigen::MatrixXd dense_k(k);
  EXPECT_LE((dense_k - Eigen::MatrixXd(k_together)).cwiseAbs().maxCoeff(),
            1e-14 * dense_k.cwiseAbs().maxCoeff());
}

TEST(FemModel, RejectsStiffnessWithAnotherPattern) {
  const FemModel model(unit_box(ElementType::tetrahedron, {1, 1, 1}), {rubber});
  const Eigen::VectorXd u = Eigen::VectorXd::Zero(model.num_dofs());
  SparseMatrix wrong(model.num_dofs(), model.num_dofs());
  EXPECT_TRUE(throws_with_message<Error>([&] { model.tangent_stiffness(u, wrong); },
                                         "does not have stiffness_pattern()'s pattern"));
  SparseMatrix k = model.stiffness_pattern();
  EXPECT_TRUE(throws_with_message<Error>(
      [&] { model.tangent_stiffness(Eigen::VectorXd::Zero(5), k); }, "vector has 5 entries"));
}

// The parallel colour sweep against an independent serial assembly: every element as its own
// one-element model, summed by the test. The mesh is large enough (2304 elements) for the model
// to use all threads; with OMP_NUM_THREADS=1 and 2 the results are bit-identical (each entry
// receives its contributions in colour order), and they match this reference to round-off
// (measured relative differences 1.8e-16 for R, 1.4e-16 for K).
TEST(FemModel, ParallelAssemblyMatchesSerialElementSum) {
  const VolumeMesh mesh = unit_box(ElementType::tetrahedron, {8, 8, 6});
  ASSERT_GE(mesh.num_elements(), 2000);
  const FemModel model(mesh, {rubber});
  const Eigen::VectorXd u = random_displacement(model.num_dofs(), 0.03, 6);

  Eigen::VectorXd reference_forces = Eigen::VectorXd::Zero(model.num_dofs());
  std::vector<Eigen::Triplet<double>> reference_entries;
  for (Eigen::Index e = 0; e < mesh.num_elements(); ++e) {
    VolumeMesh single;
    single.vertices.resize(4, 3);
    single.elements.resize(1, 4);
    Eigen::VectorXd single_u(12);
    for (int a = 0; a < 4; ++a) {
      single.vertices.row(a) = mesh.vertices.row(mesh.elements(e, a));
      single.elements(0, a) = a;
      single_u.segment<3>(3 * a) = u.segment<3>(3 * mesh.elements(e, a));
    }
    const FemModel element_model(single, {rubber});
    Eigen::VectorXd element_forces;
    SparseMatrix element_k = element_model.stiffness_pattern();
    element_model.forces_and_stiffness(single_u, element_forces, element_k);
    const Eigen::MatrixXd dense_k(element_k);
    for (int a = 0; a < 4; ++a) {
      const int row = 3 * mesh.elements(e, a);
      reference_forces.segment<3>(row) += element_forces.segment<3>(3 * a);
      for (int b = 0; b < 4; ++b) {
        for (int i = 0; i < 3; ++i) {
          for (int k = 0; k < 3; ++k) {
            reference_entries.emplace_back(row + i, 3 * mesh.elements(e, b) + k,
                                           dense_k(3 * a + i, 3 * b + k));
          }
        }
      }
    }
  }
  SparseMatrix reference_k(model.num_dofs(), model.num_dofs());
  reference_k.setFromTriplets(reference_entries.begin(), reference_entries.end());

  Eigen::VectorXd forces;
  SparseMatrix k = model.stiffness_pattern();
  model.forces_and_stiffness(u, forces, k);
  EXPECT_LT((forces - reference_forces).norm() / reference_forces.norm(), 1e-14);
  EXPECT_LT(SparseMatrix(k - reference_k).norm() / reference_k.norm(), 1e-14);

  // Repeated parallel assembly is deterministic.
  Eigen::VectorXd again;
  SparseMatrix k_again = model.stiffness_pattern();
  model.forces_and_stiffness(u, again, k_again);
  EXPECT_EQ(forces, again);
  EXPECT_TRUE(std::equal(k.valuePtr(), k.valuePtr() + k.nonZeros(), k_again.valuePtr()));
}

// A free body's rest stiffness has exactly the six rigid motions as its null space (no fixed
// vertices in the model). Eigenvalues relative to the largest, measured: the six smallest
// ≤ 4.4e-17, the seventh 4.4e-3 (both element types).
TEST(FemModel, FreeBodyRestStiffnessHasSixZeroModes) {
  for (const ElementType type : {ElementType::tetrahedron, ElementType::hexahedron}) {
    const FemModel model(unit_box(type, {2, 2, 3}), {rubber});
    SparseMatrix k = model.stiffness_pattern();
    model.tangent_stiffness(Eigen::VectorXd::Zero(model.num_dofs()), k);
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen((Eigen::MatrixXd(k)));
    const Eigen::VectorXd values = eigen.eigenvalues() / eigen.eigenvalues().maxCoeff();
    EXPECT_LT(values.head<6>().cwiseAbs().maxCoeff(), 1e-13);
    EXPECT_GT(values[6], 1e-4);
  }
}

}  // namespace
}  // namespace khz::reduced
