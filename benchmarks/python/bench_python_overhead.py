"""What calling Kilohertz from Python costs on top of the same call in C++, measured in one process
(issue 21's target: at most 3 µs more per contact query and per reduced step):

- a contact query: ContactQuery.query() called from a Python loop, against sweep(), which runs
  the same queries in a C++ loop (the elephant pressed into the dino, 128³ field);
- a reduced Newmark step: ReducedIntegrator.step() from Python against run(), the same steps in
  a C++ loop (the beam of the examples, r = 18, one Newton iteration);
- a device written in Python in the 1 kHz cycle: a run of example (g)'s scene with a Python
  device that holds still, against the same run with the scene's C++ null device at the same
  pose.

Each figure is the best of several repetitions (the least disturbed by the machine), and printed
as the C++ time, the Python time and their difference.

    PYTHONPATH=build/release/python python3 benchmarks/python/bench_python_overhead.py [--quick]
"""

import sys
import time
from pathlib import Path

import numpy as np

import kilohertz.contact as kc
import kilohertz.reduced as kr
from kilohertz import scene
from kilohertz.haptic import Device, DeviceCapabilities, DeviceState

QUICK = "--quick" in sys.argv
REPEATS = 2 if QUICK else 7
SCENES = Path(__file__).resolve().parents[2] / "examples" / "scenes"


def best_seconds(run, repeats=REPEATS):
    best = float("inf")
    for _ in range(repeats):
        start = time.perf_counter()
        run()
        best = min(best, time.perf_counter() - start)
    return best


def report(name, cpp_us, python_us, unit):
    print(f"{name:<28} C++ {cpp_us:9.2f} µs   Python {python_us:9.2f} µs   "
          f"overhead {python_us - cpp_us:7.2f} µs per {unit}")


def scaled(mesh, height):
    low, high = kr.analyze_mesh(mesh).bounding_box
    mesh.vertices[:] = (mesh.vertices - (low + high) / 2) * (height / (high - low).max())
    return mesh


def contact_query():
    meshes = scene.default_cgal_mesh_dir()
    dino = scaled(kr.read_triangle_mesh(meshes / "dino.off"), 0.2)
    elephant = scaled(kr.read_triangle_mesh(meshes / "elephant.off"), 0.05)
    field = kc.signed_distance_field(dino, cells=64 if QUICK else 128)
    tree = kc.PointTree(kc.repulsion_pointshell(elephant, cells=48, first_level_points=64,
                                                levels=3))
    count = 200 if QUICK else 2000
    poses = np.tile(np.eye(4), (count, 1, 1))
    poses[:, 0, 3] = 0.035  # pressed into the dino's side
    poses[:, 1, 3] = np.linspace(-0.01, 0.01, count)
    query = kc.ContactQuery(tree)
    in_contact = query.sweep(field, poses)["points_in_contact"].mean()
    cpp = best_seconds(lambda: query.sweep(field, poses))

    def from_python():
        for pose in poses:
            query.query(field, pose, grasp_point=pose[:3, 3])

    python = best_seconds(from_python)
    report(f"contact query ({in_contact:.0f} points)", 1e6 * cpp / count, 1e6 * python / count,
           "query")


def reduced_step():
    mesh = kr.box_hex_mesh([0, 0, 0], [0.3, 0.04, 0.02], (30, 4, 2))
    fem = kr.FemModel(mesh, kr.Material.stvk(1e6, 0.4, 1000.0))
    clamped = np.flatnonzero(mesh.vertices[:, 0] == 0.0)
    model = kr.ReducedModel.precompute(
        fem, kr.modal_derivative_basis(fem, clamped, basis_size=18, num_modes=6))
    steps = 500 if QUICK else 5000
    forces = 1e-3 * np.sin(np.outer(np.arange(steps), np.ones(model.dimension)))
    integrator = kr.reduced_newmark(model, max_newton_iterations=1)

    def in_cpp():
        integrator.reset()
        integrator.run(forces)

    def from_python():
        integrator.reset()
        for force in forces:
            integrator.step(force)

    report(f"reduced step (r = {model.dimension})", 1e6 * best_seconds(in_cpp) / steps,
           1e6 * best_seconds(from_python) / steps, "step")


class HeldStill(Device):
    """A device written in Python at a fixed pose: the cost of its calls and nothing else."""

    def __init__(self, position):
        super().__init__(DeviceCapabilities(max_force=10, max_torque=1, max_stiffness=3000))
        self.position = position
        self.time = 0.0

    def read(self):
        self.time += 1e-3
        return DeviceState(position=self.position, time=self.time)

    def write(self, force, torque):
        return True


def python_device():
    prepared = scene.prepare_scene(scene.read_scene(SCENES / "block_push.json"))
    cycles = 300 if QUICK else 3000
    null = scene.make_device({"type": "null"})
    cpp = best_seconds(lambda: scene.SceneRuntime(prepared, [null]).run(cycles=cycles))
    held = HeldStill([0.0, 0.0, 0.0])
    python = best_seconds(lambda: scene.SceneRuntime(prepared, [held]).run(cycles=cycles))
    report("1 kHz cycle, device", 1e6 * cpp / cycles, 1e6 * python / cycles, "cycle")


if __name__ == "__main__":
    contact_query()
    reduced_step()
    python_device()
