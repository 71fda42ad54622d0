"""The installed kilohertz package, imported the way a user would: PYTHONPATH set to the prefix's
site-packages, no LD_LIBRARY_PATH (.ci/run). It must come from the prefix, not the build tree,
and find its C++ libraries by itself."""

import sys
from pathlib import Path

import numpy as np

import kilohertz
from kilohertz.contact import signed_distance_field
from kilohertz.reduced import TriangleMesh, analyze_mesh

prefix = Path(sys.argv[1]).resolve()
location = Path(kilohertz.__file__).resolve()
assert prefix in location.parents, f"kilohertz imported from {location}, not from {prefix}"

# A closed tetrahedron, outward normals.
tetrahedron = TriangleMesh([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]],
                           [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])
assert analyze_mesh(tetrahedron).closed
field = signed_distance_field(tetrahedron, cells=16)
assert field.distance(np.array([0.1, 0.1, 0.1])) < 0 < field.distance(np.array([1.0, 1.0, 1.0]))
print(f"kilohertz {kilohertz.__version__} from {location.parent}: OK")
