#pragma once
// The parts of the kilohertz._core extension, one per file, each adding its classes and
// functions to the module it is given.

#include <pybind11/pybind11.h>

namespace khz::python {

namespace py = pybind11;

/// Kilohertz's exception types as Python exceptions on `module` (Error and its subclasses),
/// and the translation of every C++ exception of the libraries into them.
void bind_errors(py::module_& module);

/// kilohertz.reduced: TriangleMesh, VolumeMesh, mesh files, analyze_mesh(), repair.
void bind_reduced_meshes(py::module_& reduced);

/// kilohertz.contact: GridGeometry, DistanceGrid, distance fields of meshes, field files.
void bind_contact_fields(py::module_& contact);

}  // namespace khz::python
