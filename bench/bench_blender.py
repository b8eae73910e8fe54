"""The Blender add-on's frame (what a mouse move costs in Edit Mode) against the solver's
frame alone, on a bumpy plane with ~35k support vertices. Prints JSON with medians.

  blender -b --factory-startup --python bench/bench_blender.py -- build/blender/freeform_blender.zip
"""
import json
import os
import statistics
import sys
import tempfile
import time

import bmesh
import bpy
import numpy as np

zip_path = sys.argv[sys.argv.index("--") + 1]
os.environ.setdefault("BLENDER_USER_SCRIPTS", tempfile.mkdtemp())
bpy.ops.preferences.addon_install(filepath=os.path.abspath(zip_path), overwrite=True)
bpy.ops.preferences.addon_enable(module="freeform_blender")
import freeform_blender  # noqa: E402
from freeform_blender import session  # noqa: E402

ff = freeform_blender.native.ff
results = []
for n, radius in ((250, 0.75),):
    m = ff.make_bumpy_plane(n, n, 0.03, 3.0, 2.0, 2.0)
    me = bpy.data.meshes.new("plane")
    me.from_pydata(m.vertices.tolist(), [], m.faces.tolist())
    obj = bpy.data.objects.new("plane", me)
    bpy.context.scene.collection.objects.link(obj)
    bpy.context.view_layer.objects.active = obj
    bpy.ops.object.mode_set(mode='EDIT')
    bm = bmesh.from_edit_mesh(me)
    d = np.linalg.norm(m.vertices[:, :2] - [1.0, 1.0], axis=1)
    for mask, role in ((d < radius, 'SUPPORT'), (d < 0.1, 'HANDLE')):
        for v, on in zip(bm.verts, mask):
            v.select = bool(on)
        bmesh.update_edit_mesh(me)
        bpy.ops.freeform.assign(role=role)
    t0 = time.perf_counter()
    bpy.ops.freeform.precompute(background=False)
    precompute_ms = 1e3 * (time.perf_counter() - t0)
    s = session.get(obj)
    name = s.movable[0]
    solver_ms, frame_ms = [], []
    for i in range(30):
        t = np.eye(4)
        t[2, 3] = 0.01 * i
        transforms = {name: t}
        t0 = time.perf_counter()
        s.evaluate(transforms)
        solver_ms.append(1e3 * (time.perf_counter() - t0))
        t0 = time.perf_counter()
        s.drag(obj, transforms)  # what a mouse move does: a frame + write the support + redraw update
        frame_ms.append(1e3 * (time.perf_counter() - t0))
    results.append({"vertices": len(me.vertices), "touched": int(len(s.solver.touched)),
                    "precompute_ms": round(precompute_ms, 1),
                    "solver_frame_ms_median": round(statistics.median(solver_ms), 2),
                    "addon_frame_ms_median": round(statistics.median(frame_ms), 2),
                    "load_1min": os.getloadavg()[0]})
    bpy.ops.object.mode_set(mode='OBJECT')
print(json.dumps({"bench": "blender_addon_frame", "results": results}, indent=1))
