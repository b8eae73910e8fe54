"""The Blender add-on, headless: installed from its zip, driven through its operators like the
panel does, and checked against the freeform CLI (an independent path through the C++ core)
on the files Blender sees. Blender keeps float32 coordinates, hence the 1e-6 diagonal bound."""

import json
import os
import re
import subprocess

import bmesh
import bpy
import numpy as np
import pytest

# Empty in the run where Debian's libraries are hidden (tests/blender/CMakeLists.txt: blender_bundled),
# since the CLI needs them: the add-on's own module computes the reference there.
CLI = os.environ.get("FREEFORM_CLI")
MESHES = os.environ["FREEFORM_MESH_DIR"]
DATA = os.environ["FREEFORM_DATA_DIR"]


@pytest.fixture(scope="session")
def ff():
    bpy.ops.preferences.addon_install(filepath=os.environ["FREEFORM_BLENDER_ZIP"], overwrite=True)
    bpy.ops.preferences.addon_enable(module="freeform_blender")
    import freeform_blender
    assert freeform_blender.native.IMPORT_ERROR is None
    return freeform_blender.native.ff


@pytest.fixture
def scene(ff):
    if bpy.context.object is not None and bpy.context.object.mode != 'OBJECT':
        bpy.ops.object.mode_set(mode='OBJECT')
    for obj in list(bpy.data.objects):
        bpy.data.objects.remove(obj)
    for me in list(bpy.data.meshes):
        bpy.data.meshes.remove(me)
    return ff


def coords(obj):
    if obj.mode == 'EDIT':
        obj.update_from_editmode()
    co = np.empty(len(obj.data.vertices) * 3, dtype=np.float32)
    obj.data.vertices.foreach_get("co", co)
    return co.reshape(-1, 3)


def diagonal(points):
    return float(np.linalg.norm(points.max(axis=0) - points.min(axis=0)))


def cli_deform(mesh_path, edit_path, out_path):
    if not CLI:
        import freeform_blender
        ff = freeform_blender.native.ff
        mesh = ff.read_mesh(mesh_path)
        return ff.deform(mesh, ff.read_edit(edit_path, mesh))
    run = subprocess.run([CLI, "deform", str(mesh_path), "--edit", str(edit_path), "-o", str(out_path)],
                         capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    return read_off(out_path)


def cli_translation(obj, rest, support, handle, offset, order, tmp_path):
    """The CLI's result for the same regions and a translated handle, on Blender's own
    triangulation of the object, written by this test (not by the add-on)."""
    me = obj.data
    me.calc_loop_triangles()
    write_off(tmp_path / "tri.off", rest, np.array([t.vertices[:] for t in me.loop_triangles]))
    move = np.eye(4)
    move[:3, 3] = offset
    edit = {"order": order, "support": {"vertices": np.flatnonzero(support).tolist()},
            "handles": [{"region": {"vertices": np.flatnonzero(handle).tolist()}, "transform": {"matrix": move.tolist()}}]}
    (tmp_path / "tri.json").write_text(json.dumps(edit))
    return cli_deform(tmp_path / "tri.off", tmp_path / "tri.json", tmp_path / "cli.off")


def read_off(path):
    words = open(path).read().split()
    assert words[0] == "OFF"
    n = int(words[1])
    return np.array(words[4:4 + 3 * n], dtype=np.float64).reshape(n, 3)


def write_off(path, points, faces):
    with open(path, "w") as f:
        f.write(f"OFF\n{len(points)} {len(faces)} 0\n")
        f.writelines(f"{x!r} {y!r} {z!r}\n" for x, y, z in points.astype(np.float64).tolist())
        f.writelines(f"3 {a} {b} {c}\n" for a, b, c in faces.tolist())


def with_undo(operator, **properties):
    """Run an operator as the UI does: scripts' calls push no undo step unless asked."""
    return operator('EXEC_DEFAULT', True, **properties)


def select(obj, mask):
    bm = bmesh.from_edit_mesh(obj.data)
    for v, on in zip(bm.verts, mask):
        v.select = bool(on)
    bm.select_flush(False)
    bmesh.update_edit_mesh(obj.data)


def test_the_module_loads_the_libraries_bundled_in_the_zip(ff):
    """SuiteSparse, METIS and OpenBLAS come from the add-on's freeform/_libs, never the system's
    (Blender itself links the system's OpenBLAS: both stay apart under their own names)."""
    bundled = os.path.join(os.path.dirname(ff.__file__), "_libs")
    maps = open("/proc/self/maps").read()
    ours = set(re.findall(r"/\S*(?:cholmod|umfpack|metis|suitesparseconfig|-freeform\.so)\S*", maps))
    assert any("libopenblas-freeform" in path for path in ours), ours
    assert all(path.startswith(bundled) for path in ours), ours


def test_the_model_choices_are_the_librarys_models(ff):
    items = bpy.types.Object.bl_rna.properties["freeform"].fixed_type.properties["deformation"].enum_items
    assert [i.identifier.lower() for i in items] == list(ff.DEFORMATIONS) == ["linear", "nonlinear"]


def test_apply_edit_on_the_imported_armadillo_equals_the_cli(scene, tmp_path):
    ff = scene
    rest = ff.read_mesh(os.path.join(MESHES, "armadillo.off"))
    points = rest.vertices.astype(np.float32)  # what Blender can hold, exactly
    obj_path = tmp_path / "armadillo.obj"
    ff.write_mesh(str(obj_path), points.astype(np.float64), rest.faces)
    bpy.ops.wm.obj_import(filepath=str(obj_path), forward_axis='Y', up_axis='Z')
    obj = bpy.context.selected_objects[0]
    bpy.context.view_layer.objects.active = obj
    assert np.array_equal(coords(obj), points)  # same vertices, same order
    edit = os.path.join(DATA, "edits", "armadillo.json")
    assert bpy.ops.freeform.apply_edit(filepath=edit) == {'FINISHED'}
    got = coords(obj)
    expected = cli_deform(obj_path, edit, tmp_path / "cli.off")
    d = diagonal(points)
    assert np.abs(got - expected).max() <= 1e-6 * d
    assert np.linalg.norm(got - points, axis=1).max() > 0.02 * d  # the ear moved


def subdivided_cube():
    bpy.ops.mesh.primitive_cube_add(size=2.0)
    obj = bpy.context.active_object
    bpy.ops.object.mode_set(mode='EDIT')
    bpy.ops.mesh.select_all(action='SELECT')
    bpy.ops.mesh.subdivide(number_cuts=7)
    bpy.ops.mesh.select_all(action='DESELECT')
    return obj


def cube_with_regions(obj=None):
    """The subdivided cube's upper part as the support, its top face as a handle, assigned
    through the panel's operators; returns (object, rest positions, support, handle masks)."""
    obj = obj or subdivided_cube()
    rest = coords(obj)
    support, handle = rest[:, 2] > -0.6, rest[:, 2] > 0.9
    select(obj, support)
    assert bpy.ops.freeform.assign(role='SUPPORT') == {'FINISHED'}
    select(obj, handle)
    assert bpy.ops.freeform.assign(role='HANDLE') == {'FINISHED'}
    return obj, rest, support, handle


def test_panel_regions_on_a_quad_mesh_and_a_handle_move_equal_the_cli_and_undo(scene, tmp_path):
    obj, rest, support, handle = cube_with_regions()
    n_quads = len(obj.data.polygons)
    bpy.ops.ed.undo_push(message="regions")  # in background mode Blender starts no undo stack itself
    assert with_undo(bpy.ops.freeform.transform, mode='TRANSLATE', translate=(0.3, 0.0, 0.4)) == {'FINISHED'}
    got = coords(obj)

    expected = cli_translation(obj, rest, support, handle, (0.3, 0.0, 0.4), 2, tmp_path)
    assert np.abs(got - expected).max() <= 1e-6 * diagonal(rest)
    assert np.allclose(got[handle], rest[handle] + [0.3, 0.0, 0.4], atol=1e-6)
    assert np.array_equal(got[~support], rest[~support])
    assert len(obj.data.polygons) == n_quads and all(len(p.vertices) == 4 for p in obj.data.polygons)

    # export_edit: the file `freeform deform` replays on the written rest mesh
    bpy.ops.freeform.export_edit(filepath=str(tmp_path / "exported.json"), mesh_filepath=str(tmp_path / "rest.off"))
    replayed = cli_deform(tmp_path / "rest.off", tmp_path / "exported.json", tmp_path / "replayed.off")
    assert np.abs(got - replayed).max() <= 1e-6 * diagonal(rest)

    bpy.ops.ed.undo()
    assert np.array_equal(coords(obj), rest)


def test_a_second_move_composes_and_undo_restores_the_first(scene):
    obj, rest, _, _ = cube_with_regions()
    bpy.ops.ed.undo_push(message="regions")
    with_undo(bpy.ops.freeform.transform, mode='TRANSLATE', translate=(0.0, 0.0, 0.4))
    first = coords(obj)
    with_undo(bpy.ops.freeform.transform, mode='ROTATE', angle=np.radians(30), axis=(1.0, 0.0, 0.0))
    second = coords(obj)
    top = rest[:, 2] > 0.9
    centre = first[top].mean(axis=0)  # rotated about the handle's current centroid
    c, s = np.cos(np.radians(30)), np.sin(np.radians(30))
    r = np.array([[1, 0, 0], [0, c, -s], [0, s, c]])
    assert np.allclose(second[top], (first[top] - centre) @ r.T + centre, atol=1e-5)
    bpy.ops.ed.undo()
    assert np.array_equal(coords(obj), first)
    bpy.ops.freeform.transform(mode='TRANSLATE', translate=(0.0, 0.0, -0.4))  # back to the rest
    assert np.abs(coords(obj) - rest).max() <= 1e-6


def test_immovable_handle_stays_and_settings_and_groups_save_with_the_blend(scene, tmp_path):
    obj, rest, _, _ = cube_with_regions()
    ring = np.abs(rest[:, 2] - 0.25) < 0.05
    select(obj, ring)
    bpy.ops.freeform.assign(role='IMMOVABLE')
    obj.freeform.order = '3'
    obj.freeform.outer = 0.5
    bpy.ops.freeform.transform(mode='RESIZE', scale=(1.5, 1.5, 1.0))
    got = coords(obj)
    assert np.array_equal(got[ring], rest[ring])
    assert np.abs(got - rest).max() > 0.3
    path = str(tmp_path / "cube.blend")
    bpy.ops.object.mode_set(mode='OBJECT')
    bpy.ops.wm.save_as_mainfile(filepath=path)
    bpy.ops.wm.open_mainfile(filepath=path)
    obj = bpy.data.objects["Cube"]
    assert {g.name for g in obj.vertex_groups} == {"freeform_support", "freeform_handle_1", "freeform_immovable_1"}
    assert obj.freeform.order == '3' and obj.freeform.outer == 0.5


def error_of(call):
    with pytest.raises(RuntimeError) as raised:
        call()
    message = str(raised.value)
    assert "Traceback" not in message and "internal error" not in message
    return message


def test_bad_input_is_a_blender_error_message(scene, tmp_path):
    bpy.context.view_layer.objects.active = None
    assert "no mesh object is active" in error_of(lambda: bpy.ops.freeform.transform(mode='TRANSLATE'))
    obj = subdivided_cube()
    assert "no vertex is selected" in error_of(lambda: bpy.ops.freeform.assign(role='SUPPORT'))
    assert "support of 'Cube' is empty" in error_of(lambda: bpy.ops.freeform.transform(translate=(0, 0, 1)))
    select(obj, coords(obj)[:, 2] > -0.6)
    bpy.ops.freeform.assign(role='SUPPORT')
    assert "no movable handle" in error_of(lambda: bpy.ops.freeform.transform(translate=(0, 0, 1)))
    select(obj, coords(obj)[:, 2] > -2)  # everything: nothing left fixed, no free vertex
    bpy.ops.freeform.assign(role='HANDLE')
    message = error_of(lambda: bpy.ops.freeform.transform(translate=(0, 0, 1)))
    assert "Freeform:" in message
    bpy.ops.object.mode_set(mode='OBJECT')
    assert "not in Edit Mode" in error_of(lambda: bpy.ops.freeform.assign(role='SUPPORT'))
    missing = str(tmp_path / "missing.json")
    assert "missing.json" in error_of(lambda: bpy.ops.freeform.apply_edit(filepath=missing))
    (tmp_path / "bad.json").write_text('{"order": 2, "support": {"vertices": [999999]}}')
    assert "outside the mesh" in error_of(lambda: bpy.ops.freeform.apply_edit(filepath=str(tmp_path / "bad.json")))


def test_a_settings_change_precomputes_in_the_background_and_shows_the_new_result(scene, tmp_path):
    import freeform_blender.operators as ops
    import freeform_blender.session as session
    obj, rest, support, handle = cube_with_regions()
    bpy.ops.freeform.transform(mode='TRANSLATE', translate=(0.0, 0.3, 0.3))
    k2 = coords(obj)
    obj.freeform.order = '3'  # the panel's setting: precomputes in a thread
    s = session.get(obj)
    s.thread.join()
    while ops._poll_precompute() is not None:  # Blender's timer, run by hand (no event loop here)
        pass
    k3 = coords(obj)
    expected = cli_translation(obj, rest, support, handle, (0.0, 0.3, 0.3), 3, tmp_path)
    assert np.abs(k3 - expected).max() <= 1e-6 * diagonal(rest)
    assert np.abs(k3 - k2).max() > 1e-3  # the stiffer result differs


def test_loose_vertices_stay_and_a_non_manifold_mesh_is_refused_by_name(scene):
    obj = subdivided_cube()
    bm = bmesh.from_edit_mesh(obj.data)
    loose = bm.verts.new((0.0, 0.0, 0.5))  # inside the support's height range, in no face
    bmesh.update_edit_mesh(obj.data)
    obj, rest, _, _ = cube_with_regions(obj)
    bpy.ops.freeform.transform(mode='TRANSLATE', translate=(0.0, 0.0, 0.5))
    got = coords(obj)
    assert np.array_equal(got[-1], rest[-1]) and loose is not None
    assert np.abs(got - rest).max() >= 0.5 - 1e-6

    bpy.ops.object.mode_set(mode='OBJECT')
    me = bpy.data.meshes.new("fin")  # three triangles on one edge
    me.from_pydata([(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, -1, 0), (0, 0, 1)], [], [(0, 1, 2), (1, 0, 3), (0, 1, 4)])
    fin = bpy.data.objects.new("fin", me)
    bpy.context.scene.collection.objects.link(fin)
    bpy.context.view_layer.objects.active = fin
    bpy.ops.object.mode_set(mode='EDIT')
    bpy.ops.mesh.select_all(action='SELECT')
    bpy.ops.freeform.assign(role='SUPPORT')
    select(fin, np.array([False, False, True, False, False]))
    bpy.ops.freeform.assign(role='HANDLE')
    message = error_of(lambda: bpy.ops.freeform.transform(translate=(0, 0, 1)))
    assert "manifold" in message and "fin" in message


def test_regions_changed_on_a_moved_shape_keep_the_move_and_free_what_left(scene, tmp_path):
    obj, rest, support, handle = cube_with_regions()
    bpy.ops.freeform.transform(mode='TRANSLATE', translate=(0.0, 0.0, 0.4))
    left = support & (rest[:, 2] < -0.2)
    select(obj, left)
    bpy.ops.freeform.remove()  # the support shrinks while the handle is up
    bpy.ops.freeform.transform(mode='TRANSLATE', translate=(0.0, 0.0, 0.1))  # composes: 0.5 in total
    got = coords(obj)
    expected = cli_translation(obj, rest, support & ~left, handle, (0.0, 0.0, 0.5), 2, tmp_path)
    assert np.abs(got - expected).max() <= 1e-6 * diagonal(rest)
    assert np.array_equal(got[left], rest[left])


def enclosed_volume(positions, tris):
    p = np.asarray(positions, dtype=np.float64)
    return float(np.einsum("ij,ij->i", p[tris[:, 0]], np.cross(p[tris[:, 1]], p[tris[:, 2]])).sum() / 6.0)


def test_keep_volume_switches_the_nonlinear_models_volume_term_as_in_the_cli(scene, tmp_path):
    import freeform_blender.operators as ops
    import freeform_blender.session as session
    obj, rest, _, handle = cube_with_regions()
    obj.freeform.deformation = 'NONLINEAR'
    obj.freeform.multiresolution = False  # with it the model keeps its smooth base's volume
    volumes = {}
    for keep in (True, False):
        obj.freeform.preserve_volume = keep  # the panel's switch: precomputes again
        s = session.get(obj)
        if s is not None and s.thread is not None:
            s.thread.join()
            while ops._poll_precompute() is not None:
                pass
        # A twist: the model's rotations keep edge lengths, so without the term the part necks.
        # (A pull would add volume with it too: a drag's volume is the user's, docs/nonlinear.md.)
        bpy.ops.freeform.transform(mode='ROTATE', angle=np.radians(90), axis=(0.0, 0.0, 1.0))
        tris = np.asarray(session.get(obj).tris)  # the model's triangles (quads split as it did)
        rest_volume = enclosed_volume(rest, tris)
        volumes[keep] = enclosed_volume(coords(obj), tris)
        got = coords(obj)
        bpy.ops.freeform.export_edit(filepath=str(tmp_path / "pull.json"), mesh_filepath=str(tmp_path / "rest.off"))
        assert json.loads((tmp_path / "pull.json").read_text())["nonlinear"]["preserve_volume"] is keep
        replayed = cli_deform(tmp_path / "rest.off", tmp_path / "pull.json", tmp_path / "replayed.off")
        assert np.abs(got - replayed).max() <= 1e-5 * diagonal(rest)
        centre = rest[handle].mean(axis=0)  # turned about the handle's centroid
        turned = (rest[handle] - centre) @ np.array([[0.0, 1.0, 0.0], [-1.0, 0.0, 0.0], [0.0, 0.0, 1.0]]) + centre
        assert np.allclose(got[handle], turned, atol=1e-5)
        bpy.ops.freeform.transform(mode='ROTATE', angle=np.radians(-90), axis=(0.0, 0.0, 1.0))  # back
    assert abs(volumes[True] / rest_volume - 1.0) < 1e-5  # kept (to float32 coordinates)
    assert volumes[False] < 0.99 * rest_volume  # the twist necks without the term
