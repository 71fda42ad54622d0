#pragma once
// What one haptic cycle did for one hand (thesis Figure 4.2): for logs, plots and a render or UI
// thread.

#include <khz/contact/query/contact_wrench.hpp>
#include <khz/haptic/common.hpp>

namespace khz::haptic {

/// One hand's cycle, as World::cycle() returns it (copy it into a TripleBuffer to hand it to
/// another thread).
struct CycleRecord {
  double time = 0.0;  ///< The cycle's start on the loop's clock (s).
  Pose manipulandum;  ///< Virtual-world grasp frame of the device (last good one if invalid).
  Pose simulation;    ///< The simulation object after the coupling step.
  /// Contact on the held object at the queried pose: force, torque about the grasp point,
  /// their gradients and the query's counters (zero when no query ran).
  contact::ContactWrench contact;
  Wrench rendered;  ///< What the safety layer sent (device axes and units).
  /// F_contact + F_VC at the pose contact was queried at, with this cycle's manipulandum (N;
  /// N·m about the grasp point): how far from equilibrium (thesis eq. 4.1) the previous step left
  /// the simulation object. Zero when the coupling did not step.
  Wrench residual;
  /// Deepest point in contact over the hand's pairs, in grid spacings of the field it is in (the
  /// smallest spacing of a deformed field's domains); pairs against analytic fields, which have
  /// no grid, do not count. 0 without contact.
  double penetration_voxels = 0.0;
  /// The passivity observer after this cycle (J at the device; CycleMetrics): below zero, the
  /// simulation has given the hand more energy than it took.
  double observed_energy = 0.0;
  int degenerate_dimension = 0;     ///< §4.10's degenerate subspace this cycle.
  bool coupling_saturated = false;  ///< The coupling force or torque was saturated (eq. 4.39).
  bool device_valid = false;        ///< The device read succeeded.
  bool contact_valid = false;       ///< The contact query accepted its input.
  bool coupling_valid = false;      ///< The coupling step accepted its input.
  bool integrators_ok = true;       ///< Every deformable object's time step succeeded.
};

}  // namespace khz::haptic
