#pragma once
// Run figures as Python dicts, shared by SceneRuntime.metrics() and scene.report().

#include <khz/haptic/world/cycle_metrics.hpp>

#include <pybind11/pybind11.h>

namespace khz::python {

namespace py = pybind11;

/// {"mean", "p50", "p99", "max", "count"} of a per-cycle quantity.
py::dict quantiles_out(const haptic::Quantiles& q);

/// A hand's CycleMetricsSummary: force and torque jumps, peaks, jitter while still, equilibrium
/// residuals, penetration and the passivity observer (docs/HAPTICS.md names each).
py::dict metrics_out(const haptic::CycleMetricsSummary& s);

}  // namespace khz::python
