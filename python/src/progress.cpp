// A ProgressCallback that hands reports to Python and lets Ctrl-C through.

#include "progress.hpp"

#include <memory>
#include <string>

namespace khz::python {

reduced::ProgressCallback python_progress(const py::object& callable) {
  // One Python reference, shared by every copy and released under the GIL by the last.
  std::shared_ptr<py::object> shared(new py::object(callable), [](py::object* held) {
    const py::gil_scoped_acquire gil;
    delete held;
  });
  return [shared](const reduced::Progress& progress) {
    const py::gil_scoped_acquire gil;
    if (PyErr_CheckSignals() != 0) throw py::error_already_set();
    if (shared->is_none()) return true;
    const py::object answer = (*shared)(std::string(progress.stage), progress.done, progress.total);
    return !(answer.is(py::bool_(false)));
  };
}

}  // namespace khz::python
