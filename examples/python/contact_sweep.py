"""A contact query swept along a path: CGAL's elephant pressed into the dino's side and slid
along it, with the force, the points in contact and the query's time plotted per pose.

Both meshes are scaled to metres (the dino 20 cm tall) through the mesh's vertex view. The
elephant is a rigid pointshell (repulsion, 4 levels), the dino a 128³ signed distance field.
Runs in a few seconds.

    python3 examples/python/contact_sweep.py [OUTPUT_DIR]
"""

import sys
import time
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import kilohertz.contact as kc  # noqa: E402
import kilohertz.reduced as kr  # noqa: E402
from kilohertz.scene import default_cgal_mesh_dir  # noqa: E402


def scaled(mesh, height):
    """The mesh scaled about its box's centre so that its box is `height` (m) tall."""
    low, high = kr.analyze_mesh(mesh).bounding_box
    mesh.vertices[:] = (mesh.vertices - (low + high) / 2) * (height / (high - low).max())
    return mesh


def main(output):
    meshes = default_cgal_mesh_dir()
    if meshes is None:
        sys.exit("no CGAL meshes: set KHZ_CGAL_MESH_DIR (Debian package libcgal-demo)")
    dino = scaled(kr.read_triangle_mesh(meshes / "dino.off"), 0.2)
    elephant = scaled(kr.read_triangle_mesh(meshes / "elephant.off"), 0.05)

    start = time.perf_counter()
    field = kc.signed_distance_field(dino, cells=128)
    shell = kc.repulsion_pointshell(elephant, cells=64, first_level_points=64, levels=4)
    tree = kc.PointTree(shell)
    print(f"{field}, {shell}: prepared in {time.perf_counter() - start:.1f} s")

    # Along y at the dino's side: find where the elephant first touches, then press 5 mm deeper.
    count = 400
    heights = np.linspace(-0.06, 0.06, count)
    poses = np.tile(np.eye(4), (count, 1, 1))
    poses[:, 1, 3] = heights
    query = kc.ContactQuery(tree, kc.ContactOptions(stiffness=2000))
    for x in np.linspace(0.15, -0.1, 501):
        poses[:, 0, 3] = x
        if query.sweep(field, poses[count // 2:count // 2 + 1])["points_in_contact"][0] > 0:
            break
    poses[:, 0, 3] -= 0.005
    swept = query.sweep(field, poses)
    force = np.linalg.norm(swept["force"], axis=1)
    print(f"{count} poses: force up to {force.max():.1f} N, up to "
          f"{swept['points_in_contact'].max()} points in contact, "
          f"{np.median(swept['microseconds']):.1f} µs median per query")

    figure, axes = plt.subplots(3, 1, sharex=True, figsize=(7, 6))
    axes[0].plot(1e3 * heights, force)
    axes[0].set_ylabel("|force| (N)")
    axes[1].plot(1e3 * heights, swept["points_in_contact"])
    axes[1].set_ylabel("points in contact")
    axes[2].plot(1e3 * heights, swept["microseconds"])
    axes[2].set_ylabel("query (µs)")
    axes[2].set_xlabel("position along the dino (mm)")
    figure.tight_layout()
    output.mkdir(parents=True, exist_ok=True)
    figure.savefig(output / "contact_sweep.png", dpi=100)
    print(f"wrote {output / 'contact_sweep.png'}")


if __name__ == "__main__":
    main(Path(sys.argv[1] if len(sys.argv) > 1 else "python-examples-output"))
