#include <khz/reduced/errors.hpp>
#include <khz/reduced/fem/material.hpp>

#include <Eigen/Eigenvalues>

#include <cmath>
#include <sstream>
#include <string>

namespace khz::reduced {
namespace {

void require(bool condition, const std::string& message) {
  if (!condition) throw Error(message);
}

std::string number(double value) {
  std::ostringstream text;
  text.precision(17);
  text << value;
  return text.str();
}

void check_density(double density) {
  require(std::isfinite(density) && density > 0.0,
          "material density must be positive and finite, got " + number(density) + " kg/m³");
}

}  // namespace

LameParameters lame_from_young_poisson(double young_modulus, double poisson_ratio) {
  require(std::isfinite(young_modulus) && young_modulus > 0.0,
          "Young's modulus must be positive and finite, got " + number(young_modulus) + " Pa");
  // ν → ½ makes λ infinite (incompressible), ν ≤ −1 makes μ non-positive.
  require(std::isfinite(poisson_ratio) && poisson_ratio > -1.0 && poisson_ratio < 0.5,
          "Poisson ratio must lie in (-1, 0.5), got " + number(poisson_ratio));
  // Thesis eq. 2.13.
  return {poisson_ratio * young_modulus / ((1.0 + poisson_ratio) * (1.0 - 2.0 * poisson_ratio)),
          young_modulus / (2.0 * (1.0 + poisson_ratio))};
}

VoigtMatrix stvk_elasticity(LameParameters lame) noexcept {
  // S = λ tr(E) I + 2μE (thesis eq. 2.2). With engineering shears in E_v, S23 = 2μ E23 = μ·(2E23),
  // hence μ (not 2μ) on the shear diagonal.
  VoigtMatrix elasticity = VoigtMatrix::Zero();
  elasticity.topLeftCorner<3, 3>().setConstant(lame.lambda);
  elasticity.diagonal() += Eigen::Matrix<double, 6, 1>(2, 2, 2, 1, 1, 1) * lame.mu;
  return elasticity;
}

Material Material::stvk(double young_modulus, double poisson_ratio, double density) {
  return stvk_lame(lame_from_young_poisson(young_modulus, poisson_ratio), density);
}

Material Material::stvk_lame(LameParameters lame, double density) {
  require(std::isfinite(lame.lambda) && std::isfinite(lame.mu) && lame.mu > 0.0,
          "StVK shear modulus mu must be positive and finite, got " + number(lame.mu) + " Pa");
  // The bulk modulus λ + ⅔μ must be positive for the material to resist volume change; with
  // μ > 0 this is exactly positive definiteness of stvk_elasticity().
  require(3.0 * lame.lambda + 2.0 * lame.mu > 0.0,
          "StVK Lamé parameters need 3·lambda + 2·mu > 0 (positive bulk modulus), got lambda = " +
              number(lame.lambda) + " Pa, mu = " + number(lame.mu) + " Pa");
  check_density(density);
  return Material(stvk_elasticity(lame), density, true, lame);
}

Material Material::general(const VoigtMatrix& elasticity, double density) {
  require(elasticity.allFinite(), "elasticity matrix has a non-finite entry");
  const double scale = elasticity.cwiseAbs().maxCoeff();
  require(scale > 0.0, "elasticity matrix is zero");
  // Entries computed from engineering constants (e.g. an orthotropic compliance inverted in
  // floating point) are symmetric only to round-off; accept that, reject real asymmetry.
  constexpr double symmetry_tolerance = 1e-10;
  const double asymmetry = (elasticity - elasticity.transpose()).cwiseAbs().maxCoeff();
  require(asymmetry <= symmetry_tolerance * scale,
          "elasticity matrix is not symmetric: max |C_ij - C_ji| = " + number(asymmetry) +
              " exceeds " + number(symmetry_tolerance) + " × max |C_ij| = " + number(scale));
  // Symmetrize exactly so stiffness matrices come out symmetric to round-off.
  const VoigtMatrix symmetric = 0.5 * (elasticity + elasticity.transpose());
  // Positive definite means positive strain energy ½ E_v·C E_v for every non-zero strain. A
  // smallest eigenvalue that is positive only at round-off level is a singular material.
  const Eigen::SelfAdjointEigenSolver<VoigtMatrix> eigen(symmetric, Eigen::EigenvaluesOnly);
  const double smallest = eigen.eigenvalues()[0];
  const double largest = eigen.eigenvalues()[5];
  constexpr double definiteness_tolerance = 1e-12;
  require(smallest > definiteness_tolerance * largest,
          "elasticity matrix is not positive definite: smallest eigenvalue " + number(smallest) +
              " Pa, largest " + number(largest) + " Pa");
  check_density(density);
  return Material(symmetric, density, false, {});
}

}  // namespace khz::reduced
