"""kilohertz.contact's pointshells, trees and contact query from Python: the same forces as C++
bit for bit along a path, deformable pointshells consistent with rigid ones, files and errors."""

import numpy as np
import pytest

import kilohertz
import kilohertz.contact as kc
import kilohertz.reduced as kr


@pytest.fixture(scope="module")
def dino_field(cgal_meshes):
    return kc.signed_distance_field(kr.read_triangle_mesh(cgal_meshes / "dino.off"), cells=48)


@pytest.fixture(scope="module")
def elephant_tree(cgal_meshes):
    return kc.PointTree(kc.vertex_pointshell(kr.read_triangle_mesh(cgal_meshes / "elephant.off")))


def path_into_the_dino(count):
    """The elephant (about 0.8 units long) slid from outside into the dino's belly, turning."""
    poses = np.tile(np.eye(4), (count, 1, 1))
    s = np.linspace(0.0, 1.0, count)
    angle = 0.5 * s
    poses[:, 0, 0] = poses[:, 1, 1] = np.cos(angle)
    poses[:, 0, 1], poses[:, 1, 0] = -np.sin(angle), np.sin(angle)
    poses[:, 0, 3] = 1.5 - 1.5 * s
    poses[:, 1, 3] = 0.3
    return poses


def test_a_sweep_equals_cpp_bit_for_bit(cgal_meshes, reference, tmp_path, dino_field,
                                        elephant_tree):
    poses = path_into_the_dino(300)
    poses.tofile(tmp_path / "poses")
    reference("query", cgal_meshes / "dino.off", 48, cgal_meshes / "elephant.off",
              tmp_path / "poses", tmp_path / "cpp")
    cpp = np.fromfile(tmp_path / "cpp").reshape(-1, 6)
    swept = kc.ContactQuery(elephant_tree).sweep(dino_field, poses)
    np.testing.assert_array_equal(swept["force"], cpp[:, :3])
    np.testing.assert_array_equal(swept["torque"], cpp[:, 3:])
    assert swept["points_in_contact"][0] == 0 and swept["points_in_contact"][-1] > 10


def test_one_query_gives_the_sweeps_result_and_gradients(dino_field, elephant_tree):
    poses = path_into_the_dino(50)
    swept = kc.ContactQuery(elephant_tree).sweep(dino_field, poses)
    query = kc.ContactQuery(elephant_tree)
    for i in (0, 25, 49):
        result = query.query(dino_field, poses[i], grasp_point=poses[i, :3, 3])
        np.testing.assert_array_equal(result.force, swept["force"][i])
        assert result.force_by_translation.shape == (3, 3)
    assert result.statistics["points_in_contact"] > 0 and result.statistics["complete"]


def test_a_deformable_pointshell_at_rest_pushes_like_the_rigid_one(tmp_path):
    # A beam's top face as a pointshell, pressed onto a flat floor field below it.
    mesh = kr.box_hex_mesh([0, 0, 0], [0.2, 0.04, 0.02], (10, 2, 1))
    fem = kr.FemModel(mesh, kr.Material.stvk(1e6, 0.4, 1000.0))
    clamped = np.flatnonzero(mesh.vertices[:, 0] == 0.0)
    basis = kr.modal_derivative_basis(fem, clamped, basis_size=6, num_modes=3)
    bottom = mesh.vertices[mesh.vertices[:, 2] == 0.0]
    shell = kc.Pointshell(bottom, np.tile([0.0, 0.0, 1.0], (len(bottom), 1)))
    tree = kc.PointTree(shell)
    deformable = kc.DeformablePointTree(tree, kr.MeshEmbedding(mesh), basis)
    assert deformable.dimension == 6
    # The floor: d = z - 0.001 on a grid around the beam (every point 1 mm deep).
    geometry = kc.GridGeometry([-0.1, -0.15, -0.15], 0.01, 40)
    n = geometry.nodes_per_axis
    z = geometry.origin[2] + geometry.spacing * np.arange(n)
    floor = kc.DistanceGrid(geometry, np.broadcast_to((z - 0.001)[:, None, None], (n, n, n)), True)
    rigid = kc.ContactQuery(tree).query(floor)
    at_rest = kc.ContactQuery(deformable).query(floor, q=np.zeros(6))
    np.testing.assert_allclose(at_rest.force, rigid.force, rtol=1e-12)
    assert rigid.statistics["points_in_contact"] == len(bottom)
    assert abs(rigid.force[2]) > 0 and np.abs(rigid.force[:2]).max() < 1e-9 * abs(rigid.force[2])
    reduced_force = at_rest.pointshell_reduced_force
    assert reduced_force.shape == (6,) and np.abs(reduced_force).max() > 0
    kc.write_deformable_point_tree(tmp_path / "beam.khztree", deformable)
    again = kc.read_deformable_point_tree(tmp_path / "beam.khztree")
    q = np.linspace(-0.01, 0.01, 6)
    np.testing.assert_array_equal(
        kc.ContactQuery(again).query(floor, q=q).pointshell_reduced_force,
        kc.ContactQuery(deformable).query(floor, q=q).pointshell_reduced_force)
    with pytest.raises(ValueError, match=r"q: expected shape \(6,\)"):
        kc.ContactQuery(deformable).query(floor, q=np.zeros(5))
    with pytest.raises(ValueError, match="needs q"):
        kc.ContactQuery(deformable).query(floor)


def test_the_contact_onset_halves_a_uniform_shallow_press():
    # 36 points 1 mm deep in a floor sampled on a 1 cm grid. Within an onset deeper than that,
    # each pushes with k d²/(2δ) and counts d/δ, so once the count exceeds L the L/ℓ-scaled force
    # is L k d / 2: half of eq. 3.1's L k d, whatever δ is.
    xy = np.stack(np.meshgrid(np.arange(6), np.arange(6)), axis=-1).reshape(-1, 2) * 0.004
    points = np.column_stack([xy, np.zeros(len(xy))])
    tree = kc.PointTree(kc.Pointshell(points, np.tile([0.0, 0.0, 1.0], (len(points), 1))))
    geometry = kc.GridGeometry([-0.1, -0.1, -0.1], 0.01, 30)
    n = geometry.nodes_per_axis
    z = geometry.origin[2] + geometry.spacing * np.arange(n)
    floor = kc.DistanceGrid(geometry, np.broadcast_to((z - 0.001)[:, None, None], (n, n, n)), True)
    step = kc.ContactQuery(tree, kc.ContactOptions(onset_voxels=0)).query(floor).force
    np.testing.assert_allclose(step, [0.0, 0.0, -1000.0 * 10 * 0.001], atol=1e-12)
    for options in (kc.ContactOptions(onset_voxels=0.2), kc.ContactOptions(onset_depth=0.003)):
        assert options.onset_voxels > 0 or options.onset_depth > 0
        np.testing.assert_allclose(kc.ContactQuery(tree, options).query(floor).force, 0.5 * step,
                                   rtol=1e-6)
    with pytest.raises(kilohertz.Error, match="onset_voxels"):
        kc.ContactOptions(onset_voxels=-1)


def test_pointshell_files_round_trip(cgal_meshes, tmp_path):
    shell = kc.repulsion_pointshell(kr.read_triangle_mesh(cgal_meshes / "elephant.off"), cells=32,
                                    first_level_points=16, levels=3)
    assert len(shell.level_ends) == 3 and shell.size == shell.level_ends[-1]
    kc.write_pointshell(tmp_path / "elephant.khzshell", shell)
    again = kc.read_pointshell(tmp_path / "elephant.khzshell")
    np.testing.assert_array_equal(again.points, shell.points)
    np.testing.assert_array_equal(again.normals, shell.normals)


@pytest.mark.bad_input
def test_bad_options_and_poses_are_refused(dino_field, elephant_tree):
    with pytest.raises(kilohertz.Error, match="stiffness"):
        kc.ContactOptions(stiffness=-1)
    with pytest.raises(ValueError, match="degradation: expected"):
        kc.ContactOptions(degradation="sometimes")
    skewed = np.eye(4)
    skewed[0, 1] = 0.5
    with pytest.raises(ValueError, match="pointshell_pose: .* not a rotation"):
        kc.ContactQuery(elephant_tree).query(dino_field, skewed)
    with pytest.raises(ValueError, match=r"pointshell_poses: expected shape \(N, 4, 4\)"):
        kc.ContactQuery(elephant_tree).sweep(dino_field, np.eye(4))
