// Run figures as Python dicts: quantiles and the runtime's cycle metrics.

#include "scene_figures.hpp"

namespace khz::python {

py::dict quantiles_out(const haptic::Quantiles& q) {
  py::dict d;
  d["mean"] = q.mean;
  d["p50"] = q.p50;
  d["p99"] = q.p99;
  d["max"] = q.max;
  d["count"] = q.count;
  return d;
}

py::dict metrics_out(const haptic::CycleMetricsSummary& s) {
  py::dict d;
  d["cycles"] = s.cycles;
  d["contact_force_jump"] = quantiles_out(s.contact_force_jump);
  d["contact_torque_jump"] = quantiles_out(s.contact_torque_jump);
  d["rendered_force_jump"] = quantiles_out(s.rendered_force_jump);
  d["rendered_torque_jump"] = quantiles_out(s.rendered_torque_jump);
  d["peak_contact_force"] = s.peak_contact_force;
  d["peak_contact_torque"] = s.peak_contact_torque;
  d["peak_rendered_force"] = s.peak_rendered_force;
  d["peak_rendered_torque"] = s.peak_rendered_torque;
  d["still_translation"] = quantiles_out(s.still_translation);
  d["still_rotation"] = quantiles_out(s.still_rotation);
  d["residual_force"] = quantiles_out(s.residual_force);
  d["residual_torque"] = quantiles_out(s.residual_torque);
  d["deepest_penetration"] = s.deepest_penetration;
  d["deepest_penetration_voxels"] = s.deepest_penetration_voxels;
  d["energy"] = s.energy;
  d["lowest_energy"] = s.lowest_energy;
  return d;
}

}  // namespace khz::python
