"""A mesh file with everything it holds: polygons, texture coordinates, normals, colours as
read-only numpy arrays; written back with new positions, keeping them."""
import base64
import json
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


# An independent glTF reader for the tests: Python's json and numpy over the buffers.
def _gltf(path):
    path = pathlib.Path(path)
    data = path.read_bytes()
    if data[:4] == b"glTF":
        n = int.from_bytes(data[12:16], "little")
        doc = json.loads(data[20:20 + n])
        bins = [data[28 + n:]]
    else:
        doc = json.loads(data)
        bins = []
        for b in doc["buffers"]:
            uri = b["uri"]
            bins.append(base64.b64decode(uri.split(",", 1)[1]) if uri.startswith("data:") else
                        (path.parent / uri).read_bytes())
    return doc, bins


def _accessor(doc, bins, i):
    a = doc["accessors"][i]
    view = doc["bufferViews"][a["bufferView"]]
    width = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4}[a["type"]]
    dtype = {5126: np.float32, 5125: np.uint32, 5123: np.uint16, 5121: np.uint8}[a["componentType"]]
    size = np.dtype(dtype).itemsize * width
    stride = view.get("byteStride", size)
    start = view.get("byteOffset", 0) + a.get("byteOffset", 0)
    raw = bins[view["buffer"]]
    rows = [np.frombuffer(raw, dtype, width, start + k * stride) for k in range(a["count"])]
    return np.array(rows).reshape(a["count"], width)


def _node_matrix(node):
    if "matrix" in node:
        return np.array(node["matrix"], dtype=np.float64).reshape(4, 4).T
    m = np.eye(4)
    x, y, z, w = node.get("rotation", [0, 0, 0, 1])
    m[:3, :3] = [[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                 [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                 [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]]
    m[:3, :3] = m[:3, :3] * np.array(node.get("scale", [1, 1, 1]))
    m[:3, 3] = node.get("translation", [0, 0, 0])
    return m


def _world_positions(path):
    """Every triangle corner's world position, per primitive, in file order."""
    doc, bins = _gltf(path)
    out = []

    def walk(i, parent):
        node = doc["nodes"][i]
        m = parent @ _node_matrix(node)
        if "mesh" in node:
            for prim in doc["meshes"][node["mesh"]]["primitives"]:
                p = _accessor(doc, bins, prim["attributes"]["POSITION"]).astype(np.float64)
                idx = _accessor(doc, bins, prim["indices"]).ravel() if "indices" in prim else np.arange(len(p))
                out.append((p @ m[:3, :3].T + m[:3, 3])[idx])
        for c in node.get("children", []):
            walk(c, m)

    for root in doc["scenes"][doc.get("scene", 0)]["nodes"]:
        walk(root, np.eye(4))
    return doc, np.concatenate(out)


GLTF2 = pathlib.Path("/usr/share/assimp/models/glTF2")


@pytest.mark.skipif(not GLTF2.is_dir(), reason="assimp-testmodels not installed")
@pytest.mark.parametrize("name", ["BoxTextured-glTF/BoxTextured.gltf", "BoxTextured-glTF-Binary/BoxTextured.glb"])
@pytest.mark.parametrize("out_ext", [".gltf", ".glb"])
def test_gltf_written_back_reads_in_an_independent_reader(tmp_path, name, out_ext):
    f = freeform.read_mesh_file(GLTF2 / name)
    doc_in, corners_in = _world_positions(GLTF2 / name)
    V = f.mesh.vertices
    rot = np.array([[0.0, -1, 0], [1, 0, 0], [0, 0, 1]])
    moved = V @ rot.T * 1.5 + [0.25, -1, 2]
    freeform.write_mesh_file(tmp_path / ("out" + out_ext), f, moved)
    doc_out, corners_out = _world_positions(tmp_path / ("out" + out_ext))
    # Each corner's soup vertex, found from the input's world positions (welded exactly).
    which = [int(np.flatnonzero((V == c).all(axis=1))[0]) for c in corners_in]
    assert np.allclose(corners_out, moved[which], atol=1e-5)
    assert doc_out["materials"] == doc_in["materials"] and doc_out["textures"] == doc_in["textures"]
    for a_in, a_out in zip(doc_in["accessors"], doc_out["accessors"]):
        assert a_in["count"] == a_out["count"]


@pytest.mark.skipif(not GLTF2.is_dir(), reason="assimp-testmodels not installed")
def test_new_gltf_from_an_obj_reads_in_an_independent_reader(tmp_path):
    path = tmp_path / "quad.obj"
    path.write_text(TEXTURED)
    f = freeform.read_mesh_file(path)
    dropped = freeform.write_mesh_file(tmp_path / "quad.glb", f, f.mesh.vertices)
    assert dropped == ["1 polygon with more than 3 corners (glTF holds triangles: triangulated)",
                       "materials, material libraries (only kept when writing obj again)"]
    doc, corners = _world_positions(tmp_path / "quad.glb")
    assert corners.shape == (9, 3)  # 3 triangles
    prim = doc["meshes"][0]["primitives"][0]
    # One glTF vertex per distinct (vertex, uv, normal): vertex 1 is split by its uv seam.
    assert doc["accessors"][prim["attributes"]["POSITION"]]["count"] == 6
    assert "TEXCOORD_0" in prim["attributes"] and "NORMAL" in prim["attributes"]
    assert np.allclose(corners, f.mesh.vertices[f.mesh.faces.ravel()], atol=1e-7)


BOWTIE = """v 0 0 0
v 1 0 0
v 0.5 1 0
v 0 2 0
v 1 2 0
vt 0 0
vt 1 0
vt 0.5 1
vt 0.2 0.8
f 1/1 2/2 3/3
f 3/4 5/2 4/1
"""


def test_repair_splits_a_vertex_and_keeps_texture_coordinates(tmp_path):
    path = tmp_path / "bowtie.obj"
    path.write_text(BOWTIE)
    with pytest.raises(freeform.TopologyError, match="repair"):
        freeform.read_mesh_file(path)
    with pytest.warns(UserWarning, match="split vertex 2"):
        f = freeform.read_mesh_file(path, repair=True)
    assert f.mesh.n_vertices == 6  # vertex 2's second fan got vertex 5
    corners = f.polygon_corners.tolist()
    assert corners[2] != corners[3] and {corners[2], corners[3]} == {2, 5}
    values, index = f.uv
    assert values[index[3]].tolist() == pytest.approx([0.2, 0.8])  # each corner keeps its own
    out = tmp_path / "fixed.obj"
    freeform.write_mesh_file(out, f, f.mesh.vertices)
    back = freeform.read_mesh_file(out)  # manifold now: no repair needed
    assert back.mesh.n_vertices == 6 and back.uv is not None
    # STL's reader joins the copy with its origin again: the write says so.
    stl = tmp_path / "fixed.stl"
    dropped = freeform.write_mesh_file(stl, f, f.mesh.vertices)
    assert any("separate vertices at equal positions: 1 " in d for d in dropped)
    with pytest.raises(freeform.TopologyError):
        freeform.read_mesh_file(stl)
