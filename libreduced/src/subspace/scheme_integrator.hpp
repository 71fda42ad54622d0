#pragma once
// The one ReducedIntegrator implementation: a time-stepping scheme's workspace behind the
// interface, so that each scheme is written once as a struct with an advance().

#include <khz/reduced/subspace/reduced_integrator.hpp>

#include <string>
#include <utility>

namespace khz::reduced::detail {

/// A ReducedIntegrator that steps with `Scheme`: a type constructed from (ReducedState&, its
/// options) that keeps the state reference and whose `advance(f̃, K̃ₑ or null) noexcept` is a
/// scheme's step as ReducedIntegrator::advance() specifies it.
template <typename Scheme>
class SchemeIntegrator final : public ReducedIntegrator {
 public:
  /// @param name the scheme's name that starts error messages.
  /// @param time_step, mass_damping, stiffness_damping Δt (s), α (1/s), β (s) from `options`,
  ///        which the caller has validated.
  /// @throws Error for a force model without coordinates or an invalid mass.
  template <typename Options>
  SchemeIntegrator(ReducedForceModel& forces, const Eigen::MatrixXd& mass, std::string name,
                   double time_step, double mass_damping, double stiffness_damping,
                   const Options& options)
      : ReducedIntegrator(forces, mass, std::move(name), time_step, mass_damping,
                          stiffness_damping),
        m_scheme(shared_state(), options) {}

 private:
  ReducedStepReport advance(
      const Eigen::Ref<const Eigen::VectorXd>& external_force,
      const Eigen::Ref<const Eigen::MatrixXd>* external_stiffness) noexcept override {
    return m_scheme.advance(external_force, external_stiffness);
  }

  Scheme m_scheme;
};

}  // namespace khz::reduced::detail
