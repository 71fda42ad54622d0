#include <khz/haptic/cycle/haptic_cycle.hpp>

namespace khz::haptic {

void HapticCycle::step(double now) noexcept {
  CycleRecord& r = m_record;
  r.time = now;
  r.device_valid = m_device.read(m_state);
  r.manipulandum = m_state.pose;
  r.contact_valid = false;
  r.coupling_valid = false;
  r.integrators_ok = true;
  r.contact = {};  // a cycle that does not query reports no contact, not the last one
  r.degenerate_dimension = 0;
  Wrench rendered;  // zero unless the whole chain succeeds
  if (r.device_valid) {
    const contact::ContactResult* contact = m_scene.query(m_coupling.simulation_pose());
    r.contact_valid = contact != nullptr;
    if (r.contact_valid) {
      r.contact = *contact;
      const CouplingStep step = m_coupling.step(m_state.pose, *contact);
      r.coupling_valid = step.valid;
      r.degenerate_dimension = step.degenerate_dimension;
      if (step.valid) {
        rendered = step.rendered;
        r.integrators_ok = m_scene.advance();
      }
    }
  }
  r.simulation = m_coupling.simulation_pose();
  m_device.write(rendered);
  r.rendered = m_device.last_output();
}

}  // namespace khz::haptic
