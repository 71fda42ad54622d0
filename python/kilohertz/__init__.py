"""Kilohertz from Python: reduced deformable models and distributed contact at haptic rates.

The submodules mirror the C++ libraries:

- ``kilohertz.reduced``: meshes and mesh files, reports and repair (``khz::reduced``);
- ``kilohertz.contact``: distance fields and their point queries (``khz::contact``).

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
    reduced,
)

# `import kilohertz.reduced` and `from kilohertz.contact import ...` find the compiled submodules.
for _name in ("reduced", "contact"):
    _sys.modules[f"{__name__}.{_name}"] = getattr(_core, _name)

__all__ = [
    "Cancelled",
    "Error",
    "IoError",
    "MeshError",
    "ParseError",
    "SolverError",
    "contact",
    "reduced",
]
