"""Shared fixtures of the kilohertz Python tests: data paths and the C++ reference program."""

import os
import subprocess
from pathlib import Path

import pytest


def pytest_configure(config):
    config.addinivalue_line(
        "markers", "bad_input: feeds the module bad input; also run under the sanitizer build")


def _environment_path(name):
    value = os.environ.get(name)
    if not value:
        pytest.fail(f"{name} is not set: run these tests through ctest (tests/python/CMakeLists.txt)")
    return Path(value)


@pytest.fixture(scope="session")
def cgal_meshes():
    """CGAL's demo meshes (libcgal-demo), extracted by the build."""
    return _environment_path("KHZ_CGAL_MESH_DIR")


@pytest.fixture(scope="session")
def test_data():
    """The project's committed test files (tests/data)."""
    return _environment_path("KHZ_TEST_DATA_DIR")


@pytest.fixture(scope="session")
def scene_examples():
    """The bundled scenes (examples/scenes)."""
    return _environment_path("KHZ_SCENE_EXAMPLES_DIR")


@pytest.fixture(scope="session")
def product_cache():
    """A product cache shared by the tests' scene preparations, inside the build tree."""
    path = _environment_path("KHZ_PYTHON_SCRATCH") / "cache"
    path.mkdir(parents=True, exist_ok=True)
    return path


@pytest.fixture(scope="session")
def reference():
    """Runs khz_python_reference (tests/python/reference.cpp) and returns its standard output."""
    program = _environment_path("KHZ_PYTHON_REFERENCE")

    # The sanitized build preloads the shared ASan runtime into Python; the reference program
    # carries its own, and must not get both.
    environment = {k: v for k, v in os.environ.items() if k != "LD_PRELOAD"}

    def run(*args):
        result = subprocess.run([str(program), *map(str, args)], capture_output=True, text=True,
                                env=environment)
        assert result.returncode == 0, result.stderr
        return result.stdout

    return run
