#pragma once
// One haptic cycle (thesis §4.1, Figure 4.2): device → manipulandum → contact query → coupling
// solve → deformable time steps → wrench to the device.

#include <khz/contact/query/contact_result.hpp>
#include <khz/haptic/common.hpp>
#include <khz/haptic/coupling/virtual_coupling.hpp>
#include <khz/haptic/cycle/contact_scene.hpp>
#include <khz/haptic/device/safe_device.hpp>
#include <khz/haptic/export.hpp>

namespace khz::haptic {

/// What one cycle did: for logs, plots and a render/UI thread (copy it into a TripleBuffer).
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

/// Runs the cycle of thesis Figure 4.2 on borrowed parts (all must outlive it; none is
/// touched by another thread while the loop runs):
///   1. device.read() → the manipulandum's virtual-world grasp frame (§4.5 mapping, indexing);
///   2. scene.query(coupling.simulation_pose()) → contact force, torque and gradients;
///   3. coupling.step(manipulandum, contact) → the next simulation pose and the wrench;
///   4. scene.advance() → each deformable object's time step under its reduced contact force;
///   5. device.write(rendered), and the watchdog's end of cycle.
/// A failed read, query or step renders zero for that cycle (the safety layer zeroes a write
/// after a failed read itself) and leaves the simulation pose where it was. noexcept and
/// allocation-free, so it can run inside HapticLoop's cycle.
class KHZ_HAPTIC_API HapticCycle {
 public:
  HapticCycle(SafeDevice& device, VirtualCoupling& coupling, ContactScene& scene) noexcept
      : m_device(device), m_coupling(coupling), m_scene(scene) {}

  /// One cycle starting at `now` with deadline `deadline` (s, the loop's clock); `clock` is
  /// read again at the end for the watchdog (a callable returning seconds on the same clock).
  template <typename Clock>
  const CycleRecord& run(double now, double deadline, Clock&& clock) noexcept {
    m_device.begin_cycle(deadline);
    step(now);
    m_device.end_cycle(clock());
    return m_record;
  }

  const CycleRecord& record() const noexcept { return m_record; }

 private:
  void step(double now) noexcept;

  SafeDevice& m_device;
  VirtualCoupling& m_coupling;
  ContactScene& m_scene;
  DeviceState m_state;
  CycleRecord m_record;
};

}  // namespace khz::haptic
