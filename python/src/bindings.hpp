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

/// kilohertz.reduced: box meshes, voxelize(), tetrahedralize(), Material, FemModel, FullNewmark.
void bind_reduced_fem(py::module_& reduced);

/// kilohertz.reduced: Basis and its generators and files, ReducedModel, ReducedIntegrator,
/// reconstruction.
void bind_reduced_models(py::module_& reduced);

/// kilohertz.contact: GridGeometry, DistanceGrid, distance fields of meshes, field files.
void bind_contact_fields(py::module_& contact);

/// kilohertz.contact: pointshells, point trees, ContactOptions, ContactQuery.
void bind_contact_query(py::module_& contact);

/// kilohertz.haptic: DeviceCapabilities, DeviceState, Device (subclassable in Python),
/// TrajectoryDevice, SimulatedOperator.
void bind_haptic_devices(py::module_& haptic);

/// kilohertz.haptic: CouplingOptions, VirtualCoupling.
void bind_haptic_coupling(py::module_& haptic);

/// kilohertz.scene: read_scene(), prepare_scene(), SceneRuntime, make_device(), and the scene
/// exceptions as subclasses of `error` (kilohertz.Error).
void bind_scene(py::module_& scene, const py::handle& error);

/// kilohertz.scene.report(): what `khz report` measures, as Python data.
void bind_scene_report(py::module_& scene);

}  // namespace khz::python
