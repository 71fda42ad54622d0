#pragma once
// Progress reports and Ctrl-C for precomputations run with the GIL released.

#include <khz/reduced/progress.hpp>

#include <pybind11/pybind11.h>

namespace khz::python {

namespace py = pybind11;

/// A ProgressCallback for a computation that runs with the GIL released. At each report it takes
/// the GIL and lets Python run its pending signal handlers, so Ctrl-C raises KeyboardInterrupt
/// out of the computation (which stops within one unit of work and returns nothing); then it
/// calls `callable(stage: str, done: int, total: int)` unless `callable` is None. A return of
/// False cancels the computation (kilohertz.Cancelled); an exception the callable raises
/// propagates out of it. Copies of the callback hold no Python reference of their own, so the
/// libraries may copy and drop them without the GIL.
reduced::ProgressCallback python_progress(const py::object& callable);

}  // namespace khz::python
