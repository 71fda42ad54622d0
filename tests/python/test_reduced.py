"""kilohertz.reduced's FEM, bases, reduced models and integrators from Python: the same numbers
as C++ bit for bit (tests/python/reference.cpp, command `beam`), SciPy matrices that agree with
finite differences, and a reduced model that follows the full one."""

import pickle

import numpy as np
import pytest
import scipy.sparse

import kilohertz
import kilohertz.reduced as kr

LENGTH, WIDTH, THICKNESS = 0.3, 0.04, 0.02


@pytest.fixture(scope="module")
def beam():
    mesh = kr.box_hex_mesh([0, 0, 0], [LENGTH, WIDTH, THICKNESS], (15, 2, 2))
    fem = kr.FemModel(mesh, kr.Material.stvk(1e6, 0.4, 1000.0))
    x = mesh.vertices
    clamped = np.flatnonzero(x[:, 0] == 0.0)
    tip = np.flatnonzero(np.abs(x[:, 0] - LENGTH) < 1e-12)
    return fem, clamped, tip


@pytest.fixture(scope="module")
def model(beam):
    fem, clamped, _ = beam
    basis = kr.modal_derivative_basis(fem, clamped, basis_size=8, num_modes=4)
    return kr.ReducedModel.precompute(fem, basis)


@pytest.fixture(scope="module")
def cpp(reference, tmp_path_factory):
    out = tmp_path_factory.mktemp("beam") / "cpp"
    reference("beam", out)
    return out


def tip_load(fem, tip, newtons):
    load = np.zeros(fem.num_dofs)
    load[3 * tip + 2] = -newtons / len(tip)
    return load


def test_fem_quantities_equal_cpp_bit_for_bit(beam, cpp):
    fem, _, _ = beam
    u = np.fromfile(f"{cpp}.at")  # C++'s sin(), which NumPy's may round differently
    np.testing.assert_array_equal(fem.internal_forces(u), np.fromfile(f"{cpp}.R"))
    stiffness = fem.stiffness_matrix(u)
    assert isinstance(stiffness, scipy.sparse.csc_matrix)
    np.testing.assert_array_equal(stiffness.data, np.fromfile(f"{cpp}.K"))
    assert fem.strain_energy(u) == np.fromfile(f"{cpp}.E")[0]


def test_k_is_the_derivative_of_r_and_r_of_e(beam):
    fem, _, _ = beam
    rng = np.random.default_rng(3)
    u = 1e-3 * rng.standard_normal(fem.num_dofs)
    du = 1e-7 * rng.standard_normal(fem.num_dofs)
    difference = fem.internal_forces(u + du) - fem.internal_forces(u - du)
    np.testing.assert_allclose(difference / 2, fem.stiffness_matrix(u) @ du, rtol=1e-5, atol=1e-9)
    energy_difference = fem.strain_energy(u + du) - fem.strain_energy(u - du)
    assert energy_difference / 2 == pytest.approx(fem.internal_forces(u) @ du, rel=1e-5)
    mass = fem.mass_matrix()
    assert mass.sum() / 3 == pytest.approx(1000.0 * LENGTH * WIDTH * THICKNESS, rel=1e-12)


def test_basis_model_and_reduced_steps_equal_cpp_bit_for_bit(beam, model, cpp, tmp_path):
    fem, _, tip = beam
    kr.write_basis_npy(tmp_path / "python.npy", model.basis)
    assert (tmp_path / "python.npy").read_bytes() == cpp.with_suffix(".npy").read_bytes()
    kr.write_reduced_model(tmp_path / "python.khzmodel", model, fem.mesh)
    assert (tmp_path / "python.khzmodel").read_bytes() == \
        cpp.with_suffix(".khzmodel").read_bytes()
    np.testing.assert_array_equal(np.load(tmp_path / "python.npy"), model.basis.vectors)

    integrator = kr.reduced_newmark(model, time_step=2e-3, max_newton_iterations=10,
                                    tolerance=1e-6)
    reduced_load = model.basis.vectors.T @ tip_load(fem, tip, 0.2)
    q = integrator.run(np.tile(reduced_load, (40, 1)))
    np.testing.assert_array_equal(q, np.fromfile(f"{cpp}.q").reshape(40, -1))


def test_the_full_integrator_equals_cpp_bit_for_bit(beam, cpp):
    fem, clamped, tip = beam
    full = kr.FullNewmark(fem, clamped, time_step=2e-3, tolerance=1e-6)
    for _ in range(5):
        converged, iterations, residual = full.step(tip_load(fem, tip, 0.2))
        assert converged and iterations >= 1
    np.testing.assert_array_equal(full.displacement, np.fromfile(f"{cpp}.u"))


def test_the_reduced_model_follows_the_full_one(beam, model):
    fem, clamped, tip = beam
    full = kr.FullNewmark(fem, clamped, time_step=2e-3, tolerance=1e-6)
    reduced = kr.reduced_newmark(model, time_step=2e-3, max_newton_iterations=10, tolerance=1e-6)
    load = tip_load(fem, tip, 0.2)
    U = model.basis.vectors
    mass = fem.mass_matrix()
    for _ in range(100):
        full.step(load)
        status, _, _ = reduced.step(U.T @ load)
        assert status == "converged"
    u = full.displacement
    difference = U @ reduced.q - u
    relative = np.sqrt(difference @ (mass @ difference)) / np.sqrt(u @ (mass @ u))
    assert relative < 0.1, relative  # 8 vectors for 432 dofs
    tip_full = u.reshape(-1, 3)[tip].mean(axis=0)
    rest = fem.mesh.vertices
    tip_reduced = kr.reconstruct_positions(rest, model.basis, reduced.q)[tip].mean(axis=0) - \
        rest[tip].mean(axis=0)
    assert tip_reduced[2] == pytest.approx(tip_full[2], rel=0.1)


def test_material_edits_change_the_model_without_a_new_precompute(model):
    q = np.linspace(-0.01, 0.01, model.dimension)
    soft = model.energy(q)
    lam, mu = kr.Material.stvk(1e6, 0.4, 1000.0).lame
    model.set_lame(0, 2 * lam, 2 * mu)
    assert model.energy(q) == pytest.approx(2 * soft, rel=1e-12)
    model.set_lame(0, lam, mu)
    assert model.energy(q) == soft
    forces, stiffness = model.forces(q)
    assert forces.shape == (model.dimension,) and stiffness.shape == (model.dimension,) * 2


@pytest.mark.bad_input
def test_files_round_trip_and_refuse_another_mesh(beam, model, tmp_path):
    fem, _, _ = beam
    again = pickle.loads(pickle.dumps(model.basis))  # bases pickle by value
    np.testing.assert_array_equal(again.vectors, model.basis.vectors)
    kr.write_reduced_model(tmp_path / "beam.khzmodel", model, fem.mesh)
    again = kr.read_reduced_model(tmp_path / "beam.khzmodel", fem.mesh)
    np.testing.assert_array_equal(again.mass, model.mass)
    kr.write_basis(tmp_path / "beam.khzbasis", model.basis, fem.mesh)
    other = kr.box_hex_mesh([0, 0, 0], [LENGTH, WIDTH, THICKNESS], (14, 2, 2))
    with pytest.raises(kilohertz.Error):
        kr.read_basis(tmp_path / "beam.khzbasis", other)


@pytest.mark.bad_input
def test_bad_input_raises_clear_errors(beam, model):
    fem, clamped, _ = beam
    with pytest.raises(ValueError, match=r"u: expected shape \(432,\) or \(144, 3\), got \(10,\)"):
        fem.internal_forces(np.zeros(10))
    with pytest.raises(ValueError, match="u: row 5 is not finite"):
        fem.strain_energy(np.where(np.arange(fem.num_dofs) == 5, np.nan, 0.0))
    with pytest.raises(kilohertz.Error):
        kr.Material.stvk(1e6, 0.5, 1000.0)
    with pytest.raises(ValueError, match="metric: expected 'mass' or 'lumped_mass'"):
        kr.modal_derivative_basis(fem, clamped, metric="euclidean")
    integrator = kr.reduced_newmark(model)
    with pytest.raises(ValueError, match=r"force: expected shape \(8,\)"):
        integrator.step(np.zeros(3))
    with pytest.raises(ValueError, match=r"stiffness: expected shape \(8, 8\)"):
        integrator.step(np.zeros(8), np.zeros((3, 3)))
    with pytest.raises(kilohertz.Cancelled):
        kr.linear_modes(fem, clamped, num_modes=4, progress=lambda *report: False)


def test_a_sketch_basis_from_example_loads(beam):
    fem, clamped, tip = beam
    loads = [(tip, np.tile([0.0, 0.0, -f / len(tip)], (len(tip), 1))) for f in (0.1, 0.2, 0.4)]
    loads.append((tip, np.tile([0.0, 0.1 / len(tip), 0.0], (len(tip), 1))))
    basis = kr.sketch_basis(fem, clamped, loads, basis_size=3)
    assert basis.size == 3 and basis.vectors.shape == (fem.num_dofs, 3)
    mass = fem.mass_matrix()
    np.testing.assert_allclose(basis.vectors.T @ (mass @ basis.vectors), np.eye(3), atol=1e-9)
    with pytest.raises(kilohertz.Error):
        kr.sketch_basis(fem, clamped, [(np.array([10_000]), [[0.0, 0.0, -1.0]])], basis_size=1)


def test_volume_meshes_from_surfaces(cgal_meshes):
    dino = kr.read_triangle_mesh(cgal_meshes / "dino.off")
    voxels = kr.voxelize(dino, resolution=16, fill_interior=True)
    assert voxels.element_type == kr.ElementType.hexahedron and voxels.num_elements > 100
    tets = kr.tetrahedralize(kr.read_triangle_mesh(cgal_meshes / "cube.off"), cell_size=0.3)
    assert tets.num_elements > 6
    kr.FemModel(tets, kr.Material.stvk(1e6, 0.3, 1000.0))  # positively oriented, no slivers
    with pytest.raises(kilohertz.MeshError):
        kr.tetrahedralize(kr.read_triangle_mesh(cgal_meshes / "elephant-with-holes.off"))


def test_value_objects_pickle_and_the_others_say_why_not(beam, model):
    fem, _, _ = beam
    mesh = pickle.loads(pickle.dumps(fem.mesh))
    np.testing.assert_array_equal(mesh.elements, fem.mesh.elements)
    material = pickle.loads(pickle.dumps(kr.Material.stvk(1e6, 0.4, 1000.0)))
    assert material.lame == kr.Material.stvk(1e6, 0.4, 1000.0).lame
    with pytest.raises(TypeError, match="ReducedModel: save it with write_reduced_model"):
        pickle.dumps(model)
    with pytest.raises(TypeError, match="FemModel: pickle its VolumeMesh"):
        pickle.dumps(fem)


def test_a_basis_from_simulation_snapshots_spans_them(beam):
    fem, clamped, tip = beam
    full = kr.FullNewmark(fem, clamped, time_step=2e-3)
    snapshots = []
    for step in range(30):
        full.step(tip_load(fem, tip, 0.2 * np.sin(0.2 * step)))
        snapshots.append(full.displacement)
    snapshots = np.array(snapshots).T  # (3n, s)
    basis = kr.simulation_data_basis(fem, clamped, snapshots, 4)
    U = basis.vectors
    mass = fem.mass_matrix()
    projected = U @ (U.T @ (mass @ snapshots))  # M-orthogonal projection onto the basis
    assert np.linalg.norm(projected - snapshots) < 0.05 * np.linalg.norm(snapshots)


def test_embedded_surface_positions_and_normals_follow_q(beam, model):
    fem, _, _ = beam
    # The beam's top face as a surface: two triangles per top cell, normals up (+z).
    x = fem.mesh.vertices
    top = np.flatnonzero(np.isclose(x[:, 2], THICKNESS))
    order = top[np.lexsort((x[top, 0], x[top, 1]))].reshape(3, 16)  # 3 rows along y, 16 along x
    triangles = []
    for j in range(2):
        for i in range(15):
            a, b, c, d = order[j, i], order[j, i + 1], order[j + 1, i + 1], order[j + 1, i]
            triangles += [[a, b, c], [a, c, d]]
    surface = kr.TriangleMesh(x, np.array(triangles))
    embedded = kr.EmbeddedSurface(kr.MeshEmbedding(fem.mesh), surface, model.basis)
    q = np.zeros(model.dimension)
    np.testing.assert_allclose(embedded.positions(q), x, atol=1e-12)
    np.testing.assert_allclose(embedded.normals(q)[top], np.tile([0, 0, 1.0], (len(top), 1)),
                               atol=1e-9)
    q[0] = 0.01
    np.testing.assert_allclose(embedded.positions(q),
                               kr.reconstruct_positions(x, model.basis, q), atol=1e-12)
    assert np.abs(embedded.normals(q)[top] - [0, 0, 1.0]).max() > 1e-4  # the face tilts
