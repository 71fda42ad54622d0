// Consistent and lumped mass matrices: element values, totals, lumping, material groups.
#include <khz/reduced/fem/fem_model.hpp>
#include <khz/reduced/meshing/box_mesh.hpp>

#include <gtest/gtest.h>

#include <Eigen/Dense>

namespace khz::reduced {
namespace {

// Masses are short sums of products: round-off only (measured ≤ 5e-15 absolute on element
// entries of size 1–8, ≤ 5e-15 relative for totals and row sums).
constexpr double round_off = 1e-13;

VolumeMesh box(ElementType type, const Eigen::Vector3d& size, const Eigen::Vector3i& cells) {
  return type == ElementType::tetrahedron ? box_tet_mesh(Eigen::Vector3d::Zero(), size, cells)
                                          : box_hex_mesh(Eigen::Vector3d::Zero(), size, cells);
}

double total(const SparseMatrix& matrix) { return matrix.coeffs().sum(); }

TEST(FemMass, TetrahedronConsistentMassIsRhoVOver20) {
  VolumeMesh mesh;
  mesh.vertices.resize(4, 3);
  mesh.vertices << 0, 0, 0, 2, 0, 0, 0, 3, 0, 0, 0, 1;  // volume 1
  mesh.elements.resize(1, 4);
  mesh.elements << 0, 1, 2, 3;
  const FemModel model(mesh, {Material::stvk(1e6, 0.3, 20.0)});
  const Eigen::MatrixXd mass(model.mass_matrix());
  // ρV/20 (1 + δ_ab) I₃ with ρV = 20.
  for (int a = 0; a < 4; ++a) {
    for (int b = 0; b < 4; ++b) {
      const Eigen::Matrix3d expected = (a == b ? 2.0 : 1.0) * Eigen::Matrix3d::Identity();
      EXPECT_LT((mass.block<3, 3>(3 * a, 3 * b) - expected).norm(), round_off);
    }
  }
}

TEST(FemMass, HexahedronConsistentMassIsTensorProductOfOneDimensionalMasses) {
  const FemModel model(box(ElementType::hexahedron, {1, 1, 1}, {1, 1, 1}),
                       {Material::stvk(1e6, 0.3, 27.0 * 8.0)});
  const Eigen::MatrixXd mass(model.mass_matrix());
  // ∫φ_a φ_b = Π over axes of 1/3 (same coordinate) or 1/6 (different): with ρ = 216,
  // 8 on the diagonal, 4 / 2 / 1 for nodes differing in one / two / three coordinates. Node
  // coordinates in VTK order; mass rows are numbered by vertex.
  const Eigen::Matrix<int, 8, 3> corner = [] {
    Eigen::Matrix<int, 8, 3> c;
    c << 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0, 0, 1, 1, 0, 1, 1, 1, 1, 0, 1, 1;
    return c;
  }();
  for (int a = 0; a < 8; ++a) {
    for (int b = 0; b < 8; ++b) {
      const int differing = (corner.row(a) - corner.row(b)).cwiseAbs().sum();
      const double expected = 8.0 / (1 << differing);
      const int row = 3 * model.mesh().elements(0, a), column = 3 * model.mesh().elements(0, b);
      EXPECT_LT((mass.block<3, 3>(row, column) - expected * Eigen::Matrix3d::Identity()).norm(),
                round_off);
    }
  }
}

TEST(FemMass, TotalsAreThreeTimesTheBodyMass) {
  const Eigen::Vector3d size(2.0, 0.5, 0.75);
  const double density = 1200.0;
  const double body_mass = density * size.prod();
  for (const ElementType type : {ElementType::tetrahedron, ElementType::hexahedron}) {
    const FemModel model(box(type, size, {3, 2, 2}), {Material::stvk(1e6, 0.3, density)});
    EXPECT_NEAR(total(model.mass_matrix(MassLumping::consistent)), 3 * body_mass,
                round_off * body_mass);
    EXPECT_NEAR(total(model.mass_matrix(MassLumping::lumped)), 3 * body_mass,
                round_off * body_mass);
  }
}

TEST(FemMass, LumpedMassIsTheDiagonalOfRowSums) {
  for (const ElementType type : {ElementType::tetrahedron, ElementType::hexahedron}) {
    const FemModel model(box(type, {1, 1, 1}, {2, 2, 2}), {Material::stvk(1e6, 0.3, 1000.0)});
    const Eigen::MatrixXd consistent(model.mass_matrix(MassLumping::consistent));
    const SparseMatrix lumped = model.mass_matrix(MassLumping::lumped);
    EXPECT_EQ(lumped.nonZeros(), model.num_dofs());
    const Eigen::MatrixXd dense(lumped);
    EXPECT_EQ((dense - Eigen::MatrixXd(dense.diagonal().asDiagonal())).norm(), 0.0);
    EXPECT_LT((dense.diagonal() - consistent.rowwise().sum()).norm(),
              round_off * dense.diagonal().norm());
  }
}

TEST(FemMass, MaterialGroupsCarryTheirDensities) {
  // Cell 0 (x < 1) in group 0 (light), cell 1 (x > 1) in group 1 (heavy); each has volume 1.
  // The grouped model's mass must be the sum of one-cell models over the same vertices.
  const Material light = Material::stvk(1e6, 0.3, 100.0), heavy = Material::stvk(1e6, 0.3, 300.0);
  for (const ElementType type : {ElementType::tetrahedron, ElementType::hexahedron}) {
    VolumeMesh mesh = box(type, {2, 1, 1}, {2, 1, 1});
    const Eigen::Index per_cell = mesh.num_elements() / 2;
    mesh.element_groups.resize(mesh.num_elements());
    mesh.element_groups << Eigen::VectorXi::Zero(per_cell), Eigen::VectorXi::Ones(per_cell);
    VolumeMesh first_cell = mesh, second_cell = mesh;
    first_cell.elements = mesh.elements.topRows(per_cell).eval();
    second_cell.elements = mesh.elements.bottomRows(per_cell).eval();
    first_cell.element_groups.resize(0);
    second_cell.element_groups.resize(0);
    const FemModel model(mesh, {light, heavy});
    for (const MassLumping lumping : {MassLumping::consistent, MassLumping::lumped}) {
      const SparseMatrix mass = model.mass_matrix(lumping);
      EXPECT_NEAR(total(mass), 3 * (100.0 + 300.0), round_off * 1200.0);
      const Eigen::MatrixXd expected =
          Eigen::MatrixXd(FemModel(first_cell, {light}).mass_matrix(lumping)) +
          Eigen::MatrixXd(FemModel(second_cell, {heavy}).mass_matrix(lumping));
      EXPECT_LT((Eigen::MatrixXd(mass) - expected).norm(), round_off * expected.norm());
    }
  }
}

}  // namespace
}  // namespace khz::reduced
