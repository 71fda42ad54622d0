"""Kilohertz from Python: reduced deformable models and distributed contact at haptic rates.

The submodules mirror the C++ libraries:

- ``kilohertz.reduced``: meshes and mesh files, reports and repair (``khz::reduced``);
- ``kilohertz.contact``: distance fields and their point queries (``khz::contact``);
- ``kilohertz.haptic``: devices, including ones written in Python (``khz::haptic``);
- ``kilohertz.scene``: scene files, their preparation and runtime (``khz::scene``).

Arrays go in and out as NumPy arrays, in metres and seconds. Every set-up failure raises a
subclass of ``kilohertz.Error`` carrying the library's message (file:line for a malformed file).
See docs/PYTHON.md.
"""

import sys as _sys

from . import _core

from ._core import (
    Cancelled,
    Error,
    IoError,
    MeshError,
    ParseError,
    SolverError,
    __version__,
    contact,
    haptic,
    reduced,
    scene,
)

# `import kilohertz.reduced` and `from kilohertz.contact import ...` find the compiled submodules
# (named kilohertz.<name> by _core), and the errors print as kilohertz.Error, where users import
# them from.
for _name in ("reduced", "contact", "haptic", "scene"):
    _sys.modules[f"{__name__}.{_name}"] = getattr(_core, _name)
for _error in (Error, IoError, ParseError, MeshError, SolverError, Cancelled):
    _error.__module__ = __name__

# Meshes, materials, grids, bases and pointshells pickle by value. The classes below hold native
# state (factorisations, trees, open devices, a running world) and say how to keep them instead;
# any other class without pickling says to make it again from its arguments.
_NOT_PICKLABLE = {
    "reduced.FemModel": "pickle its VolumeMesh and materials, and build it again",
    "reduced.FullNewmark": "it refers to a FemModel; pickle its displacement and velocity",
    "reduced.ReducedModel": "save it with write_reduced_model() and read_reduced_model()",
    "reduced.ReducedIntegrator": "pickle its q and velocity; set_state() restores them",
    "reduced.LinearModes": "pickle its modes and eigenvalues arrays",
    "reduced.MeshEmbedding": "pickle the VolumeMesh and build it again",
    "reduced.EmbeddedSurface": "build it again from the embedding, surface and basis",
    "contact.PointTree": "pickle its pointshell; PointTree(pointshell) rebuilds it",
    "contact.DeformablePointTree": "save it with write_deformable_point_tree()",
    "contact.ContactQuery": "it refers to a tree; make a new one",
    "haptic.Device": "a device is a connection to hardware or a running simulation",
    "haptic.VirtualCoupling": "make a new one at the simulation pose",
    "scene.SceneDescription": "keep the scene file, dict or text and read it again",
    "scene.PreparedScene": "prepare_scene() again: it reads every product from the cache",
    "scene.SceneRuntime": "it runs a world of devices and integrators; make a new one",
}


def _refuse_pickling(reason):
    def __reduce__(self):
        raise TypeError(f"cannot pickle {type(self).__module__}.{type(self).__qualname__}: "
                        f"{reason}")
    return __reduce__


for _module_name in ("reduced", "contact", "haptic", "scene"):
    for _class in vars(getattr(_core, _module_name)).values():
        if isinstance(_class, type) and not issubclass(_class, BaseException) and \
                "__setstate__" not in vars(_class) and "__members__" not in vars(_class):
            _class.__reduce__ = _refuse_pickling(_NOT_PICKLABLE.get(
                f"{_module_name}.{_class.__name__}",
                "make it again from the arguments it was made with"))

__all__ = [
    "Cancelled",
    "Error",
    "IoError",
    "MeshError",
    "ParseError",
    "SolverError",
    "contact",
    "haptic",
    "reduced",
    "scene",
]
