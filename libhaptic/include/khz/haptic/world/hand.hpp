#pragma once
// A hand: one device holding one body of a World through its own safety layer and coupling.

#include <khz/contact/query/contact_options.hpp>
#include <khz/haptic/coupling/coupling_options.hpp>
#include <khz/haptic/device/safe_device.hpp>
#include <khz/haptic/world/cycle_metrics.hpp>

#include <Eigen/Core>

#include <optional>

namespace khz::haptic {

/// What holds a body: a device behind its safety layer, the grasp point on the body and the
/// settings of the virtual coupling (thesis ch. 4) between them. Any number of hands may hold
/// different bodies of one World (two hands: two devices, each feeling what its body touches).
struct Hand {
  /// Index of the held body in the World's bodies.
  int body = 0;
  /// The grasp point G in the held body's frame (m): the coupling's reference point, about which
  /// torques are taken. The body's pose is grasp pose · translation(−G) (orientations coincide).
  Eigen::Vector3d grasp_in_body = Eigen::Vector3d::Zero();
  /// The device, already wrapped in its safety layer (mapping, limits, watchdog); borrowed: it
  /// must outlive the World and be opened by its owner before cycles run.
  SafeDevice* device = nullptr;
  /// The hand's virtual coupling; it starts with the simulation object at the body's pose.
  CouplingOptions coupling;
  /// The role the held body touches with where both would do (it has a pointshell and a field,
  /// and so has the other body): unset, the World's ContactOptions::haptic_object.
  std::optional<contact::HapticObject> role;
  /// Bit index of the device button that grasps: pressed, the hand grasps the dynamic body its
  /// body touches (World::grasp()); let go, it releases it. −1: none (grasp() may still be
  /// called). Must differ from the safety layer's index button.
  int grasp_button = -1;
  /// When the hand's manipulandum counts as still, for its jitter figures (World::metrics()).
  CycleMetricsOptions metrics;
};

}  // namespace khz::haptic
