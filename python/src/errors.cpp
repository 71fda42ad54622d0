// Kilohertz's exceptions in Python: the same hierarchy and messages as in C++.

#include <khz/reduced/errors.hpp>

#include "bindings.hpp"

namespace khz::python {

void bind_errors(py::module_& module) {
  // pybind11 tries the translators last registered first, so each subclass is registered after
  // its base and is caught as itself, not as Error.
  const auto error = py::register_exception<reduced::Error>(module, "Error", PyExc_RuntimeError);
  error.doc() = "Base of every Kilohertz error: a set-up step failed (bad input, a file, a solve).";
  py::register_exception<reduced::IoError>(module, "IoError", error).doc() =
      "A file could not be opened, read or written (missing, permissions, disk full).";
  py::register_exception<reduced::ParseError>(module, "ParseError", error).doc() =
      "A file's content is malformed; the message starts with file:line or file: byte offset.";
  py::register_exception<reduced::MeshError>(module, "MeshError", error).doc() =
      "A mesh violates what the operation needs (an index out of range, a NaN coordinate, ...).";
  py::register_exception<reduced::SolverError>(module, "SolverError", error).doc() =
      "A numerical procedure failed (a singular matrix, a Newton solve that diverged).";
  py::register_exception<reduced::Cancelled>(module, "Cancelled", error).doc() =
      "A long computation stopped because its progress callable returned False.";
}

}  // namespace khz::python
