"""kilohertz.reduced's meshes from Python: files, reports and repair equal to C++, bad input
raising the library's exceptions."""

import pickle

import numpy as np
import pytest

import kilohertz
from kilohertz.reduced import (
    ElementType,
    TriangleMesh,
    VolumeMesh,
    analyze_mesh,
    read_triangle_mesh,
    read_volume_mesh,
    repair_mesh,
    write_triangle_mesh,
    write_volume_mesh,
)

# Closed, open (holes), a soup of separate pieces, non-manifold, with colours.
REPORTED_MESHES = ["dino.off", "elephant-with-holes.off", "hedra_open.off", "cube-ouvert.off",
                   "b9.ply", "colored_tetra.ply", "blobby_3cc.off"]


@pytest.mark.parametrize("name", REPORTED_MESHES)
def test_the_report_is_the_one_cpp_prints(cgal_meshes, reference, name):
    mesh = read_triangle_mesh(cgal_meshes / name)
    assert str(analyze_mesh(mesh)) == reference("report", cgal_meshes / name)


def test_the_report_reads_as_attributes(cgal_meshes):
    report = analyze_mesh(read_triangle_mesh(cgal_meshes / "elephant-with-holes.off"))
    assert not report.closed
    assert report.num_boundary_edges > 0
    assert report.bounding_box.shape == (2, 3)
    assert np.all(report.bounding_box[0] <= report.bounding_box[1])
    closed = analyze_mesh(read_triangle_mesh(cgal_meshes / "dino.off"))
    assert closed.closed and closed.consistently_oriented and closed.signed_volume > 0


@pytest.mark.parametrize("weld", [0.0, 1e-3])
def test_repair_matches_cpp_byte_for_byte(cgal_meshes, reference, tmp_path, weld):
    source = cgal_meshes / "elephant-with-holes.off"
    mesh = read_triangle_mesh(source)
    summary = repair_mesh(mesh, weld_tolerance=weld)
    assert summary.oriented
    write_triangle_mesh(tmp_path / "python.off", mesh)
    reference("repair", source, weld, tmp_path / "cpp.off")
    assert (tmp_path / "python.off").read_bytes() == (tmp_path / "cpp.off").read_bytes()


@pytest.mark.parametrize("extension", [".obj", ".off", ".stl", ".ply"])
@pytest.mark.parametrize("binary", [True, False])
def test_every_surface_format_reads_back_what_was_written(cgal_meshes, tmp_path, extension,
                                                          binary):
    mesh = read_triangle_mesh(cgal_meshes / "dino.off")
    write_triangle_mesh(tmp_path / f"dino{extension}", mesh, binary=binary)
    again = read_triangle_mesh(tmp_path / f"dino{extension}")
    assert again.num_triangles == mesh.num_triangles
    # STL stores float32 corners per triangle; the others keep every vertex as written.
    tolerance = 1e-6 if extension == ".stl" else 1e-12
    np.testing.assert_allclose(again.vertices[again.triangles], mesh.vertices[mesh.triangles],
                               atol=tolerance)


def test_volume_meshes_read_and_write(test_data, tmp_path):
    tets = read_volume_mesh(test_data / "volume" / "two_tets_0based.node")
    assert tets.element_type == ElementType.tetrahedron
    assert tets.elements.shape == (2, 4)
    write_volume_mesh(tmp_path / "tets.msh", tets)
    again = read_volume_mesh(tmp_path / "tets.msh")
    np.testing.assert_array_equal(again.elements, tets.elements)
    np.testing.assert_array_equal(again.vertices, tets.vertices)
    hexes = read_volume_mesh(test_data / "volume" / "hex_boundary.msh")
    assert hexes.element_type == ElementType.hexahedron and hexes.elements.shape[1] == 8


@pytest.mark.bad_input
@pytest.mark.parametrize("folder", ["obj", "off", "ply", "stl"])
def test_malformed_files_raise_the_librarys_error_naming_the_file(test_data, folder):
    files = sorted((test_data / "malformed" / folder).iterdir())
    assert files
    for file in files:
        with pytest.raises(kilohertz.Error) as raised:
            read_triangle_mesh(file)
        assert file.name in str(raised.value), str(raised.value)


@pytest.mark.bad_input
def test_a_missing_file_is_an_io_error_and_an_unknown_extension_an_error(tmp_path):
    with pytest.raises(kilohertz.IoError, match="missing.off"):
        read_triangle_mesh(tmp_path / "missing.off")
    with pytest.raises(kilohertz.Error, match=r"\.xyz"):
        read_triangle_mesh(tmp_path / "mesh.xyz")


TRIANGLE = ([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]])


@pytest.mark.bad_input
def test_a_mesh_from_arrays_checks_shapes_dtypes_values_and_indices():
    vertices, triangles = TRIANGLE
    mesh = TriangleMesh(vertices, triangles)
    assert mesh.vertices.dtype == np.float64 and mesh.triangles.dtype == np.int32
    with pytest.raises(ValueError, match=r"vertices: expected shape \(N, 3\).*\(3, 2\)"):
        TriangleMesh(np.zeros((3, 2)), triangles)
    with pytest.raises(ValueError, match="vertices: row 1 is not finite"):
        TriangleMesh([[0, 0, 0], [np.inf, 0, 0], [0, 1, 0]], triangles)
    with pytest.raises(TypeError, match="triangles: expected .* integer .* got dtype float64"):
        TriangleMesh(vertices, np.array(triangles, dtype=float))
    with pytest.raises(kilohertz.MeshError, match="vertex 3"):
        TriangleMesh(vertices, [[0, 1, 3]])
    with pytest.raises(ValueError, match="vertex_colors: expected shape"):
        TriangleMesh(vertices, triangles, vertex_colors=np.zeros((3, 3)))


def test_array_attributes_are_views_of_the_mesh():
    mesh = TriangleMesh(*TRIANGLE)
    mesh.vertices[2, 1] = 2.0  # writes into the C++ mesh
    assert analyze_mesh(mesh).surface_area == pytest.approx(1.0)
    view = mesh.vertices
    del mesh  # the view keeps the mesh alive
    assert view[2, 1] == 2.0


def test_meshes_pickle(cgal_meshes):
    mesh = read_triangle_mesh(cgal_meshes / "colored_tetra.ply")
    assert mesh.vertex_colors.shape == (mesh.num_vertices, 4)
    again = pickle.loads(pickle.dumps(mesh))
    np.testing.assert_array_equal(again.vertices, mesh.vertices)
    np.testing.assert_array_equal(again.triangles, mesh.triangles)
    np.testing.assert_array_equal(again.vertex_colors, mesh.vertex_colors)


@pytest.mark.bad_input
def test_volume_meshes_check_their_element_width():
    with pytest.raises(ValueError, match=r"elements: expected shape \(N, 8\)"):
        VolumeMesh(np.zeros((4, 3)), [[0, 1, 2, 3]], ElementType.hexahedron)
