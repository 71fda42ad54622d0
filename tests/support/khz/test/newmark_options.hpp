#pragma once
// Options of the reduced implicit integrator as the tests use them.

#include <khz/reduced/subspace/reduced_newmark.hpp>

namespace khz::test {

/// The trapezoidal rule (β̃ = ¼, γ̃ = ½) with time step Δt (s), at most `iterations` Newton
/// iterations to the relative `tolerance`, and Rayleigh damping α (1/s), β (s).
inline reduced::ReducedNewmarkOptions trapezoidal_options(double time_step, int iterations,
                                                          double tolerance,
                                                          double mass_damping = 0.0,
                                                          double stiffness_damping = 0.0) {
  reduced::ReducedNewmarkOptions options;
  options.newmark.time_step = time_step;
  options.newmark.mass_damping = mass_damping;
  options.newmark.stiffness_damping = stiffness_damping;
  options.max_newton_iterations = iterations;
  options.tolerance = tolerance;
  return options;
}

}  // namespace khz::test
