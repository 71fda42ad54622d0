#pragma once
// How a free object of a scene moves: its mass and its motion at the start (issue 20).

#include <Eigen/Core>

#include <optional>

namespace khz::scene {

/// JSON objects[i].dynamics: the object is a free rigid body (haptic::BodyDynamics), moved by
/// gravity and contact, resting on and sliding along fixed objects, pushed by held ones, and
/// picked up by a hand's grasp_button. Its mass, centre of mass and inertia are those of the
/// solid its closed surface bounds (reduced::mass_properties(), PreparedObject::mass_properties)
/// at a uniform density.
struct DynamicsDescription {
  /// "density" (kg/m³, > 0). Default 1000 (water) unless "mass" is given.
  double density = 1000.0;
  /// "mass" (kg, > 0) instead of "density": the density is the one that gives this mass.
  std::optional<double> mass;
  /// "velocity": [x, y, z] of the centre of mass at the start (m/s, world). Default 0.
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();
  /// "angular_velocity": [x, y, z] at the start (rad/s, world). Default 0.
  Eigen::Vector3d angular_velocity = Eigen::Vector3d::Zero();
};

}  // namespace khz::scene
