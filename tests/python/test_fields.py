"""kilohertz.contact's distance fields from Python: the same grid and queries as C++ bit for bit,
vectorised queries, files, progress, Ctrl-C and the GIL."""

import os
import pickle
import signal
import threading
import time

import numpy as np
import pytest

import kilohertz
from kilohertz.contact import (
    DistanceGrid,
    GridGeometry,
    read_distance_field,
    signed_distance_field,
    unsigned_distance_field,
    write_distance_field,
)
from kilohertz.reduced import read_triangle_mesh


@pytest.fixture(scope="module")
def dino(cgal_meshes):
    return read_triangle_mesh(cgal_meshes / "dino.off")


@pytest.fixture(scope="module")
def dino_field(dino):
    return signed_distance_field(dino, cells=48)


def points_around(grid, count, seed=7):
    """Points in and slightly beyond the grid's box."""
    box = grid.geometry.origin, grid.geometry.origin + grid.geometry.size
    margin = 0.1 * grid.geometry.size
    return np.random.default_rng(seed).uniform(box[0] - margin, box[1] + margin, (count, 3))


def test_field_and_queries_equal_cpp_bit_for_bit(cgal_meshes, reference, tmp_path, dino,
                                                 dino_field):
    points = points_around(dino_field, 2000)
    points.tofile(tmp_path / "points")
    reference("field", cgal_meshes / "dino.off", 48, tmp_path / "points", tmp_path / "cpp")
    write_distance_field(tmp_path / "python.khzsdf", dino_field)
    assert (tmp_path / "python.khzsdf").read_bytes() == (tmp_path / "cpp.khzsdf").read_bytes()
    distances, gradients = dino_field.distance_and_gradient(points)
    np.testing.assert_array_equal(distances, np.fromfile(tmp_path / "cpp.distance"))
    np.testing.assert_array_equal(gradients, np.fromfile(tmp_path / "cpp.gradient").reshape(-1, 3))
    np.testing.assert_array_equal(dino_field.distance(points), distances)


def test_one_point_gives_a_scalar_and_many_an_array(dino_field):
    points = points_around(dino_field, 5)
    many = dino_field.distance(points)
    assert many.shape == (5,)
    assert [dino_field.distance(p) for p in points] == list(many)
    value, gradient = dino_field.distance_and_gradient(points[0])
    assert value == many[0] and gradient.shape == (3,)
    assert dino_field.contains(points).dtype == bool
    # Lists, float32 and non-contiguous arrays are taken too (converted to float64).
    assert dino_field.distance(points.tolist()).shape == (5,)
    np.testing.assert_array_equal(dino_field.distance(np.asfortranarray(points)), many)


def test_the_signed_field_is_negative_inside_and_the_unsigned_one_positive(dino, dino_field):
    centroid = dino.vertices.mean(axis=0)
    far = dino_field.geometry.origin - 1.0
    assert dino_field.is_signed and dino_field.boundary_nodes_inside == 0
    assert dino_field.distance(far) > 0
    unsigned = unsigned_distance_field(dino, cells=16)
    assert not unsigned.is_signed and np.all(unsigned.values >= 0)
    # The values view is read-only, indexed [k, j, i].
    n = dino_field.geometry.nodes_per_axis
    assert dino_field.values.shape == (n, n, n)
    with pytest.raises(ValueError):
        dino_field.values[0, 0, 0] = 1.0
    g = dino_field.geometry
    node = g.origin + g.spacing * np.array([3, 5, 7])
    assert dino_field.distance(node) == pytest.approx(float(dino_field.values[7, 5, 3]), abs=1e-6)
    del centroid


@pytest.mark.bad_input
def test_a_grid_from_values_and_its_pickle(dino_field):
    copy = DistanceGrid(dino_field.geometry, dino_field.values, True)
    points = points_around(dino_field, 100)
    np.testing.assert_array_equal(copy.distance(points), dino_field.distance(points))
    again = pickle.loads(pickle.dumps(dino_field))
    np.testing.assert_array_equal(again.distance(points), dino_field.distance(points))
    with pytest.raises(ValueError, match="values: expected shape"):
        DistanceGrid(GridGeometry([0, 0, 0], 0.1, 4), np.zeros(10, dtype=np.float32), True)
    with pytest.raises(kilohertz.Error, match="finite"):
        DistanceGrid(GridGeometry([0, 0, 0], 0.1, 1), np.full(8, np.nan, dtype=np.float32), True)


@pytest.mark.bad_input
def test_files_round_trip_and_bad_files_raise_parse_errors(dino_field, tmp_path):
    write_distance_field(tmp_path / "dino.khzsdf", dino_field)
    again = read_distance_field(tmp_path / "dino.khzsdf")
    np.testing.assert_array_equal(again.values, dino_field.values)
    (tmp_path / "cut.khzsdf").write_bytes((tmp_path / "dino.khzsdf").read_bytes()[:1000])
    with pytest.raises(kilohertz.ParseError, match="cut.khzsdf: byte"):
        read_distance_field(tmp_path / "cut.khzsdf")
    with pytest.raises(kilohertz.IoError):
        read_distance_field(tmp_path / "missing.khzsdf")


@pytest.mark.bad_input
@pytest.mark.parametrize("bad, error, message", [
    (np.zeros((4, 2)), ValueError, r"points: expected shape \(N, 3\) or \(3,\), got \(4, 2\)"),
    ([[0, 0, np.nan]], ValueError, "points: row 0 is not finite"),
    (np.zeros((2, 3), dtype=complex), TypeError, "got dtype complex128"),
    ("points", TypeError, "got dtype <U6"),
])
def test_bad_points_raise_clear_errors(dino_field, bad, error, message):
    with pytest.raises(error, match=message):
        dino_field.distance(bad)


@pytest.mark.bad_input
def test_bad_options_raise_the_librarys_error(dino):
    with pytest.raises(kilohertz.Error, match="cells"):
        signed_distance_field(dino, cells=0)
    with pytest.raises(kilohertz.Error, match="exact_band"):
        signed_distance_field(dino, cells=8, exact_band=1.0)


@pytest.mark.bad_input
def test_progress_reports_cancels_and_propagates_exceptions(dino):
    reports = []
    signed_distance_field(dino, cells=32, progress=lambda *report: reports.append(report))
    assert reports and all(stage == "distance field" for stage, _, _ in reports)
    assert [done for _, done, _ in reports] == sorted(done for _, done, _ in reports)
    assert reports[-1][1] == reports[-1][2]
    with pytest.raises(kilohertz.Cancelled):
        signed_distance_field(dino, cells=32, progress=lambda stage, done, total: False)

    def fail(stage, done, total):
        raise RuntimeError("stop here")

    with pytest.raises(RuntimeError, match="stop here"):
        signed_distance_field(dino, cells=32, progress=fail)


def test_ctrl_c_stops_a_long_precompute_at_once(dino):
    start = time.perf_counter()
    signed_distance_field(dino, cells=160)
    full = time.perf_counter() - start
    timer = threading.Timer(0.05, lambda: os.kill(os.getpid(), signal.SIGINT))
    timer.start()
    start = time.perf_counter()
    with pytest.raises(KeyboardInterrupt):
        signed_distance_field(dino, cells=160)
    stopped = time.perf_counter() - start
    timer.join()
    assert stopped < 0.5 * full, (stopped, full)


def test_the_gil_is_released_while_a_field_is_computed(dino):
    ticks = 0
    running = True

    def count():
        nonlocal ticks
        while running:
            ticks += 1
            time.sleep(0.001)

    counter = threading.Thread(target=count)
    counter.start()
    time.sleep(0.01)
    before = ticks
    signed_distance_field(dino, cells=128)
    during = ticks - before
    running = False
    counter.join()
    assert during >= 20, during
