"""A cantilever beam, reduced (modal derivatives, r = 18) against full nonlinear FEM, side by side.

A rubber beam 30 cm long, clamped at one end, is loaded at its tip with 0.4 N over 0.4 s, held,
and let go at 0.6 s. Both models step at 2 ms; the plot shows the tip's vertical displacement in
each and the reduced model's error in the mass norm. Runs in a few seconds.

    python3 examples/python/beam_reduced_vs_full.py [OUTPUT_DIR]
"""

import sys
import time
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import kilohertz.reduced as kr  # noqa: E402

LENGTH, WIDTH, THICKNESS = 0.3, 0.04, 0.02  # m
TIP_WEIGHT = 0.4  # N, along -z
RAMP_TIME, RELEASE_TIME = 0.4, 0.6  # s
TIME_STEP, STEPS = 2e-3, 500  # s


def load_fraction(t):
    """A smooth ramp to full load, held, then let go at once."""
    if t >= RELEASE_TIME:
        return 0.0
    s = min(t / RAMP_TIME, 1.0)
    return s * s * (3.0 - 2.0 * s)


def main(output):
    mesh = kr.box_hex_mesh([0, 0, 0], [LENGTH, WIDTH, THICKNESS], (30, 4, 2))
    fem = kr.FemModel(mesh, kr.Material.stvk(1e6, 0.4, 1000.0))  # rubber: Pa, -, kg/m³
    x = mesh.vertices
    clamped = np.flatnonzero(x[:, 0] == 0.0)
    tip = np.flatnonzero(np.isclose(x[:, 0], LENGTH))

    start = time.perf_counter()
    basis = kr.modal_derivative_basis(fem, clamped, basis_size=18, num_modes=6)
    model = kr.ReducedModel.precompute(fem, basis)
    print(f"{basis.recipe}; precomputed in {time.perf_counter() - start:.2f} s")

    full = kr.FullNewmark(fem, clamped, time_step=TIME_STEP, tolerance=1e-6)
    reduced = kr.reduced_newmark(model, time_step=TIME_STEP, max_newton_iterations=10,
                                 tolerance=1e-6)
    weight = np.zeros(fem.num_dofs)
    weight[3 * tip + 2] = -TIP_WEIGHT / len(tip)
    U = basis.vectors
    reduced_weight = U.T @ weight  # f̃ = Uᵀ f
    mass = fem.mass_matrix()

    times, tip_full, tip_reduced, error, norm = [], [], [], [], []
    full_seconds = reduced_seconds = 0.0
    for step in range(STEPS):
        t = (step + 1) * TIME_STEP
        share = load_fraction(t)
        begin = time.perf_counter()
        full.step(share * weight)
        full_seconds += time.perf_counter() - begin
        begin = time.perf_counter()
        reduced.step(share * reduced_weight)
        reduced_seconds += time.perf_counter() - begin
        u, u_reduced = full.displacement, U @ reduced.q
        difference = u_reduced - u
        times.append(t)
        tip_full.append(u.reshape(-1, 3)[tip, 2].mean())
        tip_reduced.append(u_reduced.reshape(-1, 3)[tip, 2].mean())
        error.append(np.sqrt(difference @ (mass @ difference)))
        norm.append(np.sqrt(u @ (mass @ u)))
    relative = 100 * np.array(error) / max(norm)  # % of the largest deflection, mass norm
    print(f"per step: full {1e3 * full_seconds / STEPS:.2f} ms, "
          f"reduced {1e6 * reduced_seconds / STEPS:.1f} µs (from Python)")
    print(f"deepest tip: full {1e3 * min(tip_full):.2f} mm, reduced {1e3 * min(tip_reduced):.2f} mm")

    figure, (top, bottom) = plt.subplots(2, 1, sharex=True, figsize=(7, 5))
    top.plot(times, 1e3 * np.array(tip_full), label="full FEM")
    top.plot(times, 1e3 * np.array(tip_reduced), "--", label=f"reduced, r = {basis.size}")
    top.set_ylabel("tip displacement z (mm)")
    top.legend()
    bottom.plot(times, relative)
    bottom.set_ylabel("‖u_r − u‖_M / max ‖u‖_M (%)")
    bottom.set_xlabel("time (s)")
    figure.tight_layout()
    output.mkdir(parents=True, exist_ok=True)
    figure.savefig(output / "beam.png", dpi=100)
    print(f"largest error: {relative.max():.1f} % of the largest deflection (mass norm)")
    print(f"wrote {output / 'beam.png'}")


if __name__ == "__main__":
    main(Path(sys.argv[1] if len(sys.argv) > 1 else "python-examples-output"))
