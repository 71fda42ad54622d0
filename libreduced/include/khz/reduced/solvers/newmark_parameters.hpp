#pragma once
// Parameters of the implicit Newmark integrator, shared by the full and the reduced models.

#include <khz/reduced/export.hpp>

namespace khz::reduced {

/// Implicit Newmark time stepping with Rayleigh damping C = αM + βK(u) (thesis §2.7 eq. 2.33,
/// §2.9). β̃ = ¼, γ̃ = ½ (the default) is the unconditionally stable, energy-conserving
/// trapezoidal rule; β̃ = 0, γ̃ = ½ is explicit central differences.
struct KHZ_REDUCED_API NewmarkParameters {
  double time_step = 1e-3;         ///< Δt (s), > 0.
  double beta = 0.25;              ///< β̃ ∈ [0, ½].
  double gamma = 0.5;              ///< γ̃ ∈ [0, 1].
  double mass_damping = 0.0;       ///< Rayleigh α (1/s), ≥ 0.
  double stiffness_damping = 0.0;  ///< Rayleigh β (s), ≥ 0.

  /// @throws Error naming the first parameter out of range (or not finite). Implicit
  /// integrators also need β̃ > 0.
  void validate() const;
};

/// The constants α1…α6 of thesis §2.9 for given parameters (β̃ > 0):
/// a_{n+1} = α1 Δu − α2 v_n − α3 a_n, v_{n+1} = α4 Δu + α5 v_n + α6 a_n, Δu = u_{n+1} − u_n.
struct KHZ_REDUCED_API NewmarkConstants {
  double alpha1, alpha2, alpha3, alpha4, alpha5, alpha6;

  /// @throws Error if the parameters are invalid or β̃ = 0.
  static NewmarkConstants from(const NewmarkParameters& parameters);
};

}  // namespace khz::reduced
