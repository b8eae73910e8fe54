"""Mesh from and to numpy, reading and writing every format, the generators."""
import numpy as np
import pytest

import freeform


def test_numpy_round_trip(plane):
    V, F = plane.vertices, plane.faces
    assert V.dtype == np.float64 and V.shape == (169, 3) and V.flags.c_contiguous
    assert F.dtype == np.int64 and F.shape == (288, 3)
    mesh = freeform.Mesh(V, F)
    assert np.array_equal(mesh.vertices, V) and np.array_equal(mesh.faces, F)
    assert (mesh.n_vertices, mesh.n_faces, mesh.n_edges) == (169, 288, 456)


def test_arrays_are_copies(plane):
    V = plane.vertices
    V[0] = 99.0
    assert plane.vertices[0, 0] == 0.0  # the mesh is unchanged; a new array each time
    assert not np.shares_memory(plane.vertices, plane.vertices)


@pytest.mark.parametrize("convert", [
    lambda V, F: (V.astype(np.float32), F.astype(np.int32)),                        # other dtypes
    lambda V, F: (np.asfortranarray(V), np.asfortranarray(F)),                      # column-major
    lambda V, F: (np.repeat(V, 2, axis=0)[::2], np.repeat(F, 2, axis=0)[::2]),      # strided
    lambda V, F: (V.tolist(), F.tolist()),                                          # lists
    lambda V, F: (V.astype(">f8"), F.astype(np.uint16)),                            # big endian, unsigned
    lambda V, F: (np.round(V * 12).astype(np.int64), F.astype(np.uint64)),           # integer positions
])
def test_inputs_are_converted_never_misread(plane, convert):
    V, F = plane.vertices, plane.faces
    V2, F2 = convert(V, F)
    mesh = freeform.Mesh(V2, F2)
    assert np.array_equal(mesh.vertices, np.asarray(V2, dtype=np.float64))
    assert np.array_equal(mesh.faces, F)


def test_float32_is_converted_exactly():
    V = np.array([[0.1, 0, 0], [1, 0.3, 0], [0, 1, 0.7]], dtype=np.float32)
    mesh = freeform.Mesh(V, [[0, 1, 2]])
    assert np.array_equal(mesh.vertices, V.astype(np.float64))


@pytest.mark.parametrize("ext,binary,exact", [
    ("off", True, True), ("obj", True, True), ("ply", True, True), ("ply", False, True),
    ("stl", True, False), ("stl", False, False)])
def test_write_read_each_format(tmp_path, ext, binary, exact):
    mesh = freeform.make_bumpy_plane(7, 5, 0.013, 2)
    V, F = mesh.vertices, mesh.faces
    V[:, 0] += 1 / 3  # digits that do not fit a float
    path = tmp_path / f"m.{ext}"
    freeform.write_mesh(path, V, F, binary=binary)
    back = freeform.read_mesh(path)
    assert not list(tmp_path.glob("*.tmp*"))  # the atomic write left no temporary
    if exact:
        assert np.array_equal(back.vertices, V) and np.array_equal(back.faces, F)
    else:  # STL: float32 corners, welded; compare the triangles corner by corner
        assert back.n_faces == len(F)
        assert np.array_equal(back.vertices[back.faces], V.astype(np.float32).astype(np.float64)[F])


def test_write_a_mesh_object_and_path_types(tmp_path, plane):
    freeform.write_mesh(str(tmp_path / "a.off"), plane)
    freeform.write_mesh(bytes(tmp_path / "b.off"), plane.vertices, plane.faces)
    for name in ("a.off", "b.off"):
        assert np.array_equal(freeform.read_mesh(tmp_path / name).vertices, plane.vertices)


def test_read_warnings_become_python_warnings(tmp_path):
    path = tmp_path / "quad.off"
    path.write_text("OFF\n4 1 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n")
    with pytest.warns(UserWarning, match="fan-triangulated"):
        mesh = freeform.read_mesh(path)
    assert mesh.n_faces == 2


def test_repair_splits_a_non_manifold_vertex():
    # two triangles sharing only vertex 0 (a bow tie)
    V = [[0, 0, 0], [1, 0, 0], [1, 1, 0], [-1, 0, 0], [-1, -1, 0]]
    F = [[0, 1, 2], [0, 3, 4]]
    with pytest.raises(freeform.TopologyError, match="repair"):
        freeform.Mesh(V, F)
    with pytest.warns(UserWarning, match="repair"):
        mesh = freeform.Mesh(V, F, repair=True)
    assert mesh.n_vertices == 6


def test_generators():
    assert freeform.make_icosphere(2).n_vertices == 162
    assert freeform.make_disk(3).n_vertices == 1 + 6 + 12 + 18
    assert freeform.make_cylinder(2, 8).n_vertices == 24
    bumpy = freeform.make_bumpy_plane(10, 10, 0.1, 1)
    assert np.ptp(bumpy.vertices[:, 2]) > 0.1
    assert "169 vertices" in repr(freeform.make_plane(12, 12))


def test_sanitized_build_runs_under_the_sanitizers():
    """Under the asan preset (FREEFORM_PYTHON_SANITIZED=1) the ASan runtime must really be loaded."""
    import os
    if os.environ.get("FREEFORM_PYTHON_SANITIZED") != "1":
        pytest.skip("not the sanitizer build")
    with open("/proc/self/maps") as maps:
        assert "libasan" in maps.read()
