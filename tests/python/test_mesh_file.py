"""A mesh file with everything it holds: polygons, texture coordinates, normals, colours as
read-only numpy arrays; written back with new positions, keeping them."""
import os
import pathlib

import numpy as np
import pytest

import freeform

TEXTURED = """mtllib quad.mtl
v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
v 2 0.5 0
vt 0 0
vt 1 0
vt 1 1
vt 0 1
vt 0.5 0.5
vn 0 0 1
usemtl red
f 1/1/1 2/2/1 3/3/1 4/4/1
f 2/5/1 5/5/1 3/3/1
"""


def test_attributes_are_read_only_arrays(tmp_path):
    path = tmp_path / "quad.obj"
    path.write_text(TEXTURED)
    f = freeform.read_mesh_file(path)
    assert f.format == "obj" and f.mesh.n_vertices == 5 and f.mesh.n_faces == 3
    assert f.polygon_offsets.tolist() == [0, 4, 7]
    assert f.polygon_corners.tolist() == [0, 1, 2, 3, 1, 4, 2]
    values, index = f.uv
    assert values.shape == (5, 2) and index.tolist() == [0, 1, 2, 3, 4, 4, 2]  # vertex 1: uv 1 and 4, a seam
    assert f.normals is not None and f.normals[0].shape == (1, 3)
    assert f.vertex_attributes == {} and f.face_attributes == {}
    with pytest.raises(ValueError):
        values[0, 0] = 5.0


def test_write_mesh_file_keeps_the_file(tmp_path):
    path = tmp_path / "quad.obj"
    path.write_text(TEXTURED)
    f = freeform.read_mesh_file(path)
    assert freeform.write_mesh_file(tmp_path / "same.obj", f, f.mesh.vertices) == []
    assert (tmp_path / "same.obj").read_text() == TEXTURED  # unchanged positions: byte for byte
    V = f.mesh.vertices
    V[4, 2] = 1.0
    freeform.write_mesh_file(tmp_path / "moved.obj", f, V)
    lines = (tmp_path / "moved.obj").read_text().splitlines()
    assert lines[5] == "v 2 0.5 1"
    assert [l for l in lines if not l.startswith(("v ", "vn "))] == \
        [l for l in TEXTURED.splitlines() if not l.startswith(("v ", "vn "))]
    dropped = freeform.write_mesh_file(tmp_path / "moved.ply", f, V)
    assert any("texture coordinates with seams" in d for d in dropped)
    assert any("materials" in d for d in dropped)
    back = freeform.read_mesh_file(tmp_path / "moved.ply")
    assert back.polygon_offsets.tolist() == [0, 4, 7]
    assert np.array_equal(back.mesh.vertices, V)
    with pytest.raises(freeform.Error, match="positions given"):
        freeform.write_mesh_file(tmp_path / "bad.obj", f, V[:3])


@pytest.mark.skipif(not os.path.isdir("/usr/share/assimp/models/PLY"), reason="assimp-testmodels not installed")
def test_ply_colours_are_exposed():
    f = freeform.read_mesh_file(pathlib.Path("/usr/share/assimp/models/PLY/float-color.ply"))
    color = f.vertex_attributes["color"]
    assert color.shape[0] == f.mesh.n_vertices and color.shape[1] in (3, 4)
    assert 0.0 <= color.min() and color.max() <= 1.0
