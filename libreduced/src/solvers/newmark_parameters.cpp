#include <khz/reduced/errors.hpp>
#include <khz/reduced/solvers/newmark_parameters.hpp>

#include <cmath>
#include <string>

namespace khz::reduced {
namespace {

void require(bool ok, const char* name, double value, const char* range) {
  if (!ok) {
    throw Error(std::string("Newmark parameter ") + name + " = " + std::to_string(value) +
                " must be " + range);
  }
}

}  // namespace

void NewmarkParameters::validate() const {
  require(std::isfinite(time_step) && time_step > 0, "time_step", time_step, "positive");
  require(beta >= 0 && beta <= 0.5, "beta", beta, "in [0, 0.5]");
  require(gamma >= 0 && gamma <= 1, "gamma", gamma, "in [0, 1]");
  require(std::isfinite(mass_damping) && mass_damping >= 0, "mass_damping", mass_damping,
          "finite and non-negative");
  require(std::isfinite(stiffness_damping) && stiffness_damping >= 0, "stiffness_damping",
          stiffness_damping, "finite and non-negative");
}

NewmarkConstants NewmarkConstants::from(const NewmarkParameters& p) {
  p.validate();
  require(p.beta > 0, "beta", p.beta, "positive for an implicit integrator");
  // Thesis §2.9, the constants after the algorithm listing.
  const double h = p.time_step;
  return {1.0 / (p.beta * h * h), 1.0 / (p.beta * h),     (1.0 - 2.0 * p.beta) / (2.0 * p.beta),
          p.gamma / (p.beta * h), 1.0 - p.gamma / p.beta, (1.0 - p.gamma / (2.0 * p.beta)) * h};
}

}  // namespace khz::reduced
