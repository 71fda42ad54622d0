#pragma once
// The reduced external force of point forces on mesh vertices, per time step.

#include <khz/reduced/basis/force_load.hpp>
#include <khz/reduced/export.hpp>

#include <Eigen/Core>

#include <span>

namespace khz::reduced {

/// f̃ = Uᵀ f for a force f made of point forces on mesh vertices (the reduced external force of
/// thesis §2.9), reading only the three rows of U at each loaded vertex: 3r multiply-adds per
/// point force instead of a 3n×r product, no allocation, no exception. The per-step path of
/// interactive loads (a user's push on a few vertices); contact forces on pointshell points go
/// through their embedded modes U_s instead (EmbeddedSurface).
/// @param basis U, 3n×r (metres per unit of q).
/// @param forces vertices in [0, n) and forces (N); a vertex may repeat (its forces add up).
/// @param reduced_force r entries (asserted in debug builds), overwritten with f̃.
/// @return false, with f̃ set to zero, if a vertex is outside [0, n) or a force is not finite.
KHZ_REDUCED_API bool reduced_point_forces(const Eigen::Ref<const Eigen::MatrixXd>& basis,
                                          std::span<const PointForce> forces,
                                          Eigen::Ref<Eigen::VectorXd> reduced_force) noexcept;

}  // namespace khz::reduced
