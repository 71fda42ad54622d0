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
  Wrench rendered;               ///< What the safety layer sent (device axes).
  int degenerate_dimension = 0;  ///< §4.10's degenerate subspace this cycle.
  bool device_valid = false;     ///< The device read succeeded.
  bool contact_valid = false;    ///< The contact query accepted its input.
  bool coupling_valid = false;   ///< The coupling step accepted its input.
  bool integrators_ok = true;    ///< Every deformable object's time step succeeded.
};

}  // namespace khz::haptic
