"""A haptic run with a device written in Python: example (g)'s paddle pushes a free 0.5 kg
block across a table (static friction 0.5, kinetic 0.4), moved by a Python class standing in for
your hardware's SDK. The World runs in C++; each cycle calls the device's read() and write().

The plot shows the push on the paddle and where hand and paddle are: the block sticks until the
push reaches μ_s m g = 2.45 N, then slides (the mean push while it slides is printed). Prepared
in about a second the first time (then cached), run in about a second.

    python3 examples/python/python_device.py [OUTPUT_DIR]
"""

import sys
import time
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from kilohertz import scene  # noqa: E402
from kilohertz.haptic import Device, DeviceCapabilities, DeviceState  # noqa: E402

SCENE = Path(__file__).resolve().parent.parent / "scenes" / "block_push.json"


class ScriptedHand(Device):
    """Holds still for 0.3 s, then moves 2 cm/s along x, like the scene's own operator; keeps
    what it is asked to render, as a hardware device would send it to its motors."""

    def __init__(self):
        super().__init__(DeviceCapabilities(name="scripted hand", max_force=10, max_torque=1,
                                            max_stiffness=3000))
        self.time = 0.0
        self.forces = []

    def open(self):
        self.time = 0.0
        self.forces.clear()

    def read(self):
        self.time += 1e-3
        x = 0.02 * min(max(self.time - 0.3, 0.0), 3.0)
        return DeviceState(position=[x, 0.0, 0.0], linear_velocity=[0.0, 0.0, 0.0],
                           time=self.time)

    def write(self, force, torque):
        self.forces.append(force[0])
        return True


def main(output):
    start = time.perf_counter()
    prepared = scene.prepare_scene(scene.read_scene(SCENE))
    print(f"prepared in {time.perf_counter() - start:.1f} s ({prepared.computed} computed)")
    hand = ScriptedHand()
    runtime = scene.SceneRuntime(prepared, [hand])
    start = time.perf_counter()
    rows = runtime.run(duration=3.5)[0]
    seconds = time.perf_counter() - start
    print(f"{len(rows['time'])} cycles in {seconds:.2f} s "
          f"({1e6 * seconds / len(rows['time']):.0f} µs per cycle with the Python device)")
    push = -rows["contact_force"][:, 0]  # the block pushes the paddle back along -x
    block = runtime.pose(1)[:3, 3]
    sliding = (rows["time"] > 1.5) & (rows["time"] < 3.0)
    print(f"largest push {push.max():.2f} N, {push[sliding].mean():.2f} N while sliding; block "
          f"ended at x = {1e3 * block[0]:.1f} mm; lowest passivity observer "
          f"{runtime.metrics(0)['lowest_energy']:.4f} J")

    figure, (top, bottom) = plt.subplots(2, 1, sharex=True, figsize=(7, 5))
    top.plot(rows["time"], push, label="contact on the paddle")
    top.axhline(0.5 * 0.5 * 9.81, color="gray", linestyle=":", label="μ_s m g")
    top.axhline(0.4 * 0.5 * 9.81, color="gray", linestyle="--", label="μ_k m g")
    top.set_ylabel("push (N)")
    top.legend()
    bottom.plot(rows["time"], 1e3 * rows["manipulandum_position"][:, 0], label="hand")
    bottom.plot(rows["time"], 1e3 * rows["simulation_position"][:, 0], label="paddle")
    bottom.set_ylabel("x (mm)")
    bottom.set_xlabel("time (s)")
    bottom.legend()
    figure.tight_layout()
    output.mkdir(parents=True, exist_ok=True)
    figure.savefig(output / "python_device.png", dpi=100)
    print(f"wrote {output / 'python_device.png'}")


if __name__ == "__main__":
    main(Path(sys.argv[1] if len(sys.argv) > 1 else "python-examples-output"))
