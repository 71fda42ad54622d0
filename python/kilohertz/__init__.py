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
