#pragma once
// Linear (geometrically nonlinear) elastic materials: StVK and general anisotropic.

#include <khz/reduced/export.hpp>

#include <Eigen/Core>

namespace khz::reduced {

/// 6×6 elasticity matrix in Voigt notation: S_v = C E_v with the second Piola–Kirchhoff stress
/// S_v = (S11, S22, S33, S23, S13, S12) and the Green–Lagrange strain with engineering shears
/// E_v = (E11, E22, E33, 2E23, 2E13, 2E12). Units: Pa.
using VoigtMatrix = Eigen::Matrix<double, 6, 6>;

/// Lamé parameters (Pa).
struct LameParameters {
  double lambda = 0.0;
  double mu = 0.0;
};

/// λ = νE/((1+ν)(1−2ν)), μ = E/(2(1+ν)) (thesis eq. 2.13).
/// @throws Error unless E > 0 and −1 < ν < ½ (both finite).
KHZ_REDUCED_API LameParameters lame_from_young_poisson(double young_modulus, double poisson_ratio);

/// A linear material law S = C : E (thesis eq. 2.14) with its mass density. StVK materials
/// remember λ and μ so later layers can keep their contributions apart (runtime material
/// changes, thesis §2.11).
class KHZ_REDUCED_API Material {
 public:
  /// Isotropic StVK, S = λ tr(E) I + 2μE (thesis eq. 2.2), from Young's modulus E (Pa), Poisson
  /// ratio ν and density ρ (kg/m³). @throws Error for E ≤ 0, ν ∉ (−1, ½), ρ ≤ 0 or non-finite.
  static Material stvk(double young_modulus, double poisson_ratio, double density);
  /// Isotropic StVK from Lamé parameters (Pa). @throws Error unless μ > 0, 3λ + 2μ > 0, ρ > 0.
  static Material stvk_lame(LameParameters lame, double density);
  /// General linear material from its Voigt matrix, which must be symmetric (the major symmetry
  /// C_ijkl = C_klij; asymmetry up to 1e-10 × max |C_ij| is accepted and removed) and positive
  /// definite (a stable material; smallest eigenvalue > 1e-12 × largest). @throws Error
  /// otherwise, or for a non-finite entry or ρ ≤ 0.
  static Material general(const VoigtMatrix& elasticity, double density);

  const VoigtMatrix& elasticity() const noexcept { return m_elasticity; }
  double density() const noexcept { return m_density; }
  /// True for materials made by stvk() or stvk_lame().
  bool is_stvk() const noexcept { return m_is_stvk; }
  /// λ and μ of an StVK material (zero for general materials).
  const LameParameters& lame() const noexcept { return m_lame; }

 private:
  Material(const VoigtMatrix& elasticity, double density, bool is_stvk, LameParameters lame)
      : m_elasticity(elasticity), m_density(density), m_is_stvk(is_stvk), m_lame(lame) {}

  VoigtMatrix m_elasticity;
  double m_density;
  bool m_is_stvk;
  LameParameters m_lame;
};

/// The StVK elasticity matrix λ 1 1ᵀ + μ diag(2, 2, 2, 1, 1, 1) in the Voigt convention above.
KHZ_REDUCED_API VoigtMatrix stvk_elasticity(LameParameters lame) noexcept;

}  // namespace khz::reduced
