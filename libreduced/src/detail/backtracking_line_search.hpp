#pragma once
// The backtracking line search the static Newton solvers (full and reduced) share.

#include <cmath>
#include <optional>

namespace khz::reduced::detail {

/// What a line search needs to know about a trial point x + α d.
struct TrialMerits {
  double residual_norm;  ///< ‖R − f‖ there.
  double energy;         ///< Potential energy Π = E − fᵀx there.
};

/// Step length α for a Newton direction d from x, halving from α = 1 until one of two merits
/// accepts the trial point: the potential energy by the Armijo condition
/// Π(α) ≤ Π(0) + 1e-4 α Π′(0) (the Newton direction descends on it wherever the stiffness is
/// positive definite), or the out-of-balance norm, which falls below `residual_norm`. Accepting
/// either avoids the tiny steps a residual-only search takes in bending, where the residual often
/// grows on the way to the minimum; the residual still guards steps where the stiffness is
/// indefinite. A trial with a non-finite residual is rejected.
///
/// @param energy        Π(0).
/// @param slope         Π′(0) = (R − f)ᵀd.
/// @param residual_norm ‖R − f‖ at x.
/// @param evaluate      evaluate(α) → TrialMerits at x + α d; the last call is at the α returned.
/// @return α, or nullopt if 30 halvings found no acceptable point.
template <typename Evaluate>
std::optional<double> backtracking_line_search(double energy, double slope, double residual_norm,
                                               Evaluate&& evaluate) {
  constexpr int max_halvings = 30;
  double length = 1.0;
  for (int halving = 0; halving <= max_halvings; ++halving, length *= 0.5) {
    const TrialMerits trial = evaluate(length);
    const bool energy_decreases = slope < 0.0 && trial.energy <= energy + 1e-4 * length * slope;
    if (std::isfinite(trial.residual_norm) &&
        (energy_decreases || trial.residual_norm < residual_norm)) {
      return length;
    }
  }
  return std::nullopt;
}

}  // namespace khz::reduced::detail
