#pragma once
// The interface reduced integrators use to query a reduced model's elastic forces.

#include <khz/reduced/export.hpp>

#include <Eigen/Core>

namespace khz::reduced {

/// Reduced internal forces R̃(q) = UᵀR(Uq) and reduced tangent stiffness K̃(q) = UᵀK(Uq)U of an
/// r-dimensional reduced model (thesis eq. 2.23, 2.25), and the strain energy E(q) whose
/// gradient R̃ is. q are reduced coordinates (u = Uq); R̃ is in N·(m per unit q), K̃ its
/// derivative, E in J.
///
/// Implementations keep preallocated workspaces, so a model is not safe to use from two threads
/// at once (make one per thread). Evaluations neither allocate nor throw when the sizes are right
/// (`forces` r entries, `stiffness` r×r, both presized by the caller); wrong sizes are a
/// programming error caught by assertions in debug builds. Non-finite q gives non-finite
/// results, which integrators detect.
class KHZ_REDUCED_API ReducedForceModel {
 public:
  virtual ~ReducedForceModel();

  /// r, the number of reduced coordinates.
  virtual Eigen::Index dimension() const noexcept = 0;

  /// R̃(q) into `forces` and K̃(q) (symmetric, both triangles filled) into `stiffness`.
  virtual void evaluate(const Eigen::Ref<const Eigen::VectorXd>& q,
                        Eigen::Ref<Eigen::VectorXd> forces,
                        Eigen::Ref<Eigen::MatrixXd> stiffness) noexcept = 0;
  /// R̃(q) alone (what explicit integrators need).
  virtual void evaluate_forces(const Eigen::Ref<const Eigen::VectorXd>& q,
                               Eigen::Ref<Eigen::VectorXd> forces) noexcept = 0;
  /// Strain energy E(q) with E(0) = 0 (J).
  virtual double energy(const Eigen::Ref<const Eigen::VectorXd>& q) noexcept = 0;

 protected:
  ReducedForceModel() = default;
  ReducedForceModel(const ReducedForceModel&) = default;
  ReducedForceModel& operator=(const ReducedForceModel&) = default;
};

}  // namespace khz::reduced
