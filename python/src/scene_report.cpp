// kilohertz.scene.report(): what `khz report` measures, as Python data: the run and its summary,
// the contact query's speed against error over the run's states in contact, and the stability
// map (khz::scene::run_scene, summarize, sweep_contact, stability_map).

#include <khz/scene/contact_sweep.hpp>
#include <khz/scene/run_scene.hpp>
#include <khz/scene/run_summary.hpp>
#include <khz/scene/scene_runtime.hpp>
#include <khz/scene/stability_map.hpp>

#include <pybind11/stl.h>

#include <cmath>
#include <string>
#include <vector>

#include "bindings.hpp"
#include "progress.hpp"
#include "scene_figures.hpp"

namespace khz::python {

namespace {

py::dict summary_out(const scene::RunSummary& s) {
  py::dict d;
  d["cycles"] = s.cycles;
  d["duration"] = s.duration;
  d["cycle_us"] = quantiles_out(s.cycle_us);
  d["query_us"] = quantiles_out(s.query_us);
  d["query_us_in_contact"] = quantiles_out(s.query_us_in_contact);
  d["cycles_in_contact"] = s.cycles_in_contact;
  d["failed_cycles"] = s.failed_cycles;
  d["incomplete_cycles"] = s.incomplete_cycles;
  d["max_contacts"] = s.max_contacts;
  d["max_nodes"] = s.max_nodes;
  d["deepest_level"] = s.deepest_level;
  d["max_force"] = s.max_force;
  d["max_torque"] = s.max_torque;
  d["max_rendered_force"] = s.max_rendered_force;
  d["finite"] = s.finite;
  d["metrics"] = metrics_out(s.metrics);
  return d;
}

py::dict sweep_out(const scene::SweepResult& r) {
  py::dict d;
  d["name"] = r.name;
  d["query_us"] = quantiles_out(r.query_us);
  d["mean_nodes"] = r.mean_nodes;
  d["force_error"] = r.force_error;
  d["torque_error"] = r.torque_error;
  d["max_force_error"] = r.max_force_error;
  d["states"] = r.states;
  return d;
}

py::dict stability_out(const scene::StabilityPoint& p) {
  py::dict d;
  d["name"] = p.setting.name();
  d["key"] =
      p.setting.as_given ? std::string() : std::string(scene::parameter_key(p.setting.parameter));
  d["value"] = p.setting.value;
  d["factor"] = p.factor;
  d["refused"] = p.refused;
  d["finite"] = p.finite;
  d["cycles"] = p.cycles;
  d["peak_contact_force"] = p.peak_contact_force;
  d["contact_jump_p99"] = p.contact_jump_p99;
  d["rendered_jump_p99"] = p.rendered_jump_p99;
  d["still_step_p99"] = p.still_step_p99;
  d["deepest_voxels"] = p.deepest_voxels;
  d["lowest_energy"] = p.lowest_energy;
  d["stable"] = p.stable();
  d["smooth"] = p.smooth();
  return d;
}

py::dict report(scene::PreparedScene& prepared, double duration, bool stability,
                const py::object& progress) {
  if (!(duration >= 0.0) || !std::isfinite(duration)) {
    throw py::value_error("duration: expected 0 (the scene's own) or more seconds, got " +
                          std::to_string(duration));
  }
  const reduced::ProgressCallback report_progress = python_progress(progress);
  scene::HandRows rows;
  scene::RunSummary summary;
  std::vector<scene::SweepResult> sweep;
  std::vector<scene::StabilityPoint> map;
  {
    const py::gil_scoped_release unlocked;
    scene::SceneRuntime runtime(prepared);
    std::vector<scene::RecordedState> states;
    scene::RunOptions options;
    options.duration = duration;
    options.frame_every = 1;
    const std::size_t cycles = scene::run_cycles(runtime, duration);
    options.on_frame = [&](int cycle, scene::SceneRuntime& running) {
      states.push_back(scene::record_state(running));
      return report_progress(
          {"running", static_cast<std::int64_t>(cycle) + 1, static_cast<std::int64_t>(cycles)});
    };
    rows = scene::run_scene(runtime, options);
    summary = scene::summarize(rows.front(), 1.0 / prepared.description.loop.rate_hz);
    summary.metrics = runtime.world().metrics(0);
    sweep = scene::sweep_contact(
        runtime, states,
        scene::default_sweep(prepared.description.contact, scene::tree_levels(prepared)),
        scene::default_sweep_states, report_progress);
    if (stability) {
      map = scene::stability_map(prepared, scene::default_stability_settings(prepared.description),
                                 duration, {}, report_progress);
    }
  }
  py::dict out;
  out["summary"] = summary_out(summary);
  py::list sweep_rows, map_rows;
  for (const auto& r : sweep) sweep_rows.append(sweep_out(r));
  for (const auto& p : map) map_rows.append(stability_out(p));
  out["sweep"] = sweep_rows;
  out["stability"] = map_rows;
  return out;
}

}  // namespace

void bind_scene_report(py::module_& module) {
  module.def("report", &report, py::arg("prepared"), py::arg("duration") = 0.0, py::kw_only(),
             py::arg("stability") = true, py::arg("progress") = py::none(),
             R"(What `khz report` measures, as data: the scene run with its own devices for
`duration` s (0: its natural duration), then its states in contact replayed at every level of
detail and under time budgets, then (stability=True) the stability map, the scene run again
with one parameter changed at a time. Returns a dict: "summary" (the run's cycles, costs,
contacts, peaks, and the runtime's metrics), "sweep" (one dict per setting, the reference
first: name, query_us spread, mean_nodes, force_error, torque_error, max_force_error, states)
and "stability" (one dict per run: name, key, value, factor, refused, peak_contact_force,
contact_jump_p99 and rendered_jump_p99 in % of the peak, still_step_p99 m, deepest_voxels,
lowest_energy J, stable, smooth). Runs without the GIL; progress and Ctrl-C as prepare_scene().)");
}

}  // namespace khz::python
